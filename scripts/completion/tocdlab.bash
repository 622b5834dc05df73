# bash completion for tocdlab. Subcommands and options are read from tocdlab's own --help
# output, so the completion always matches the installed version.
_tocdlab_help_words() {
  # $1: the section to read ("Subcommands" or "Options"); the rest: the command words.
  local section=$1
  shift
  "$@" --help 2>/dev/null | awk -v want="$section" '
    /^[A-Za-z].*:$/ { in_section = ($0 ~ "^" want ":"); next }
    in_section && /^  +[-a-z]/ {
      if (want == "Subcommands") { print $1; next }
      # "-o,--output TEXT REQUIRED": the names before the first word without a dash
      n = split($1, names, ",")
      for (i = 1; i <= n; i++) if (names[i] ~ /^-/) print names[i]
    }'
}

_tocdlab() {
  local cur=${COMP_WORDS[COMP_CWORD]}
  local prev=${COMP_WORDS[COMP_CWORD - 1]}
  case "$prev" in
    --db | --csv | --json | --lab | --optics | --fit | --config | -o | --output | --mesh)
      COMPREPLY=($(compgen -f -- "$cur"))
      return
      ;;
  esac
  # The command so far: tocdlab and the subcommand words before the cursor (not options).
  local words=("${COMP_WORDS[0]}") i
  for ((i = 1; i < COMP_CWORD; i++)); do
    case "${COMP_WORDS[i]}" in -*) break ;; *) words+=("${COMP_WORDS[i]}") ;; esac
  done
  if [[ "$cur" == -* ]]; then
    COMPREPLY=($(compgen -W "$(_tocdlab_help_words Options "${words[@]}")" -- "$cur"))
  else
    local subs
    subs=$(_tocdlab_help_words Subcommands "${words[@]}")
    if [[ -n "$subs" ]]; then
      COMPREPLY=($(compgen -W "$subs" -- "$cur"))
    else
      COMPREPLY=($(compgen -f -- "$cur"))
    fi
  fi
}
complete -F _tocdlab tocdlab
