# bash completion for tocdlab. Subcommands, options and what each option takes are read from
# tocdlab's own --help output (CLI11's layout), so the completion always matches the
# installed version: no list here can drift from the program.

# The "Subcommands:" of `WORDS... --help`, one name a line.
_tocdlab_subcommands() {
  "$@" --help 2>/dev/null | awk '
    /^[A-Za-z].*:$/ { in_section = ($0 == "Subcommands:"); next }
    in_section && /^  +[a-z]/ { print $1 }'
}

# The options of `WORDS... --help`, one a line: "NAME KIND [VALUES...]". KIND is
#   flag   the option takes no value ("--json   machine-readable output": two or more
#          spaces, or the end of the line, after the names);
#   enum   CLI11 lists its values: "TEXT:{fast,paper}=fast", "ENUM:value in {a->0,b->1}";
#   dir    "TEXT:DIR";
#   number INT, UINT, FLOAT: nothing to complete;
#   file   any other value (TEXT, TEXT:FILE, ...).
# The word `positional` alone on a line says the command takes positional arguments.
_tocdlab_options() {
  "$@" --help 2>/dev/null | awk '
    /^[A-Za-z].*:$/ { section = $0; next }
    section == "Positionals:" && /^  +[^ ]/ { print "positional"; next }
    section != "Options:" || !/^  +-/ { next }
    {
      line = $0
      sub(/^ +/, "", line)
      names = line
      sub(/ .*/, "", names)
      rest = substr(line, length(names) + 1)
      if (rest == "" || rest ~ /^  /) { kind = "flag"; values = "" }
      else {
        spec = substr(rest, 2)
        sub(/ .*/, "", spec)
        values = ""
        if (match(rest, /\{[^}]*\}/)) {
          kind = "enum"
          n = split(substr(rest, RSTART + 1, RLENGTH - 2), v, ",")
          for (i = 1; i <= n; i++) { sub(/->.*/, "", v[i]); values = values " " v[i] }
        } else if (spec ~ /^TEXT:DIR/) kind = "dir"
        else if (spec ~ /^(U?INT|FLOAT)/) kind = "number"
        else kind = "file"
      }
      n = split(names, nm, ",")
      for (i = 1; i <= n; i++) if (nm[i] ~ /^-/) print nm[i], kind values
    }'
}

_tocdlab() {
  local cur=${COMP_WORDS[COMP_CWORD]} prev=${COMP_WORDS[COMP_CWORD - 1]}
  # `--mesh=<TAB>`: bash splits at "=", so the option is the word before it.
  if [[ "$prev" == "=" && $COMP_CWORD -ge 2 ]]; then
    prev=${COMP_WORDS[COMP_CWORD - 2]}
  elif [[ "$cur" == "=" ]]; then
    prev=${COMP_WORDS[COMP_CWORD - 1]}
    cur=""
  fi
  # The command so far: tocdlab and the subcommand words before the cursor (not options).
  local words=("${COMP_WORDS[0]}") i
  for ((i = 1; i < COMP_CWORD; i++)); do
    case "${COMP_WORDS[i]}" in -* | =) break ;; *) words+=("${COMP_WORDS[i]}") ;; esac
  done
  local options
  options=$(_tocdlab_options "${words[@]}")
  # A value for the option before the cursor, completed by what the option takes.
  if [[ "$prev" == -* ]]; then
    local name kind values
    while read -r name kind values; do
      [[ "$name" == "$prev" ]] || continue
      case "$kind" in
        enum) COMPREPLY=($(compgen -W "$values" -- "$cur")); return ;;
        dir) COMPREPLY=($(compgen -d -- "$cur")); return ;;
        number) COMPREPLY=(); return ;;
        file) COMPREPLY=($(compgen -f -- "$cur")); return ;;
      esac
      break  # a flag: the word at the cursor is a new one
    done <<<"$options"
  fi
  local names
  names=$(awk '$1 != "positional" { print $1 }' <<<"$options")
  if [[ "$cur" == -* ]]; then
    COMPREPLY=($(compgen -W "$names" -- "$cur"))
    return
  fi
  local subs
  subs=$(_tocdlab_subcommands "${words[@]}")
  if [[ -n "$subs" && ${#words[@]} -eq $COMP_CWORD ]]; then
    COMPREPLY=($(compgen -W "$subs" -- "$cur"))
  elif grep -qx positional <<<"$options"; then
    COMPREPLY=($(compgen -f -- "$cur"))
  else
    COMPREPLY=($(compgen -W "$names" -- "$cur"))
  fi
}
complete -F _tocdlab tocdlab
