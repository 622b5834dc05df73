#!/usr/bin/env bash
# Checks the bash completion against a tocdlab binary: after a flag (--json) TAB offers
# options, never file names; after an enumerated option it offers exactly the values --help
# lists; after a file option, files; at the start, the subcommands.
#   check_completion.sh TOCDLAB COMPLETION_SCRIPT
set -euo pipefail
bin=$1
# shellcheck source=/dev/null
source "$2"
complete -p tocdlab | grep -q -- '-F _tocdlab' || { echo "check_completion: tocdlab has no completion" >&2; exit 1; }

# A scratch directory with files, so that a completion that offers file names shows them.
scratch=$(mktemp -d)
trap 'rm -rf "$scratch"' EXIT
cd "$scratch"
touch optics.toml mesh.node notes.txt
failures=0

# complete WORDS...: what TAB offers for the last word (COMP_WORDS as bash sets them).
complete_words() {
  COMP_WORDS=("$bin" "$@")
  COMP_CWORD=$((${#COMP_WORDS[@]} - 1))
  COMPREPLY=()
  _tocdlab
  printf '%s\n' "${COMPREPLY[@]}" | sort | tr '\n' ' ' | sed 's/ $//'
}

expect() {  # expect "WHAT" "GOT" "WANTED"
  if [ "$2" = "$3" ]; then
    echo "check_completion: $1: '$2'"
  else
    echo "check_completion: $1: got '$2', want '$3'" >&2
    failures=$((failures + 1))
  fi
}
expect_no_files() {  # expect_no_files "WHAT" "GOT"
  if grep -qE '(optics\.toml|mesh\.node|notes\.txt)' <<<"$2" || [ -z "$2" ]; then
    echo "check_completion: $1: got '$2', want options and no file names" >&2
    failures=$((failures + 1))
  else
    echo "check_completion: $1: no file names (${2:0:60}...)"
  fi
}

expect_no_files "mc --json TAB" "$(complete_words mc --json '')"
expect_no_files "predict --baseline TAB" "$(complete_words predict --baseline '')"
expect "predict --mesh TAB" "$(complete_words predict --mesh '')" "fast paper"
expect "predict --mesh=TAB" "$(complete_words predict --mesh = '')" "fast paper"
expect "predict --optics TAB" "$(complete_words predict --optics '')" "graded threshold water"
expect "mc --vtu-format TAB" "$(complete_words mc --vtu-format '')" "ascii binary"
expect "--log-level e TAB" "$(complete_words --log-level e)" "error"
expect "mc --optics TAB" "$(complete_words mc --optics '')" "mesh.node notes.txt optics.toml"
expect "mc --photons TAB" "$(complete_words mc --photons '')" ""
expect "demo --truth-cleared-n TAB" "$(complete_words demo --truth-cleared-n '')" ""
expect "demo --delayed-clearing TAB" "$(complete_words demo --delayed-clearing '')" ""
expect "simlab --truth-seed TAB" "$(complete_words simlab --truth-seed '')" ""
expect "run --truth-relax TAB" "$(complete_words run --truth-relax)" "--truth-relaxation-fraction --truth-relaxation-time"
expect "study TAB" "$(complete_words study '')" "paper sensitivity sweep"
expect_no_files "identify --mechanics-only TAB" "$(complete_words identify --mechanics-only '')"
expect "identify --db TAB" "$(complete_words identify --db '')" "mesh.node notes.txt optics.toml"
expect "identify --prony-terms TAB" "$(complete_words identify --prony-terms '')" ""
expect "mc --vtu-f TAB" "$(complete_words mc --vtu-f)" "--vtu-format"
[ "$failures" -eq 0 ]
