#!/usr/bin/env bash
# Checks that the installed tocdlab(1) documents every subcommand, nested ones included, and
# every option of each: the subsection "tocdlab <command> options:" lists each option that
# `tocdlab <command> --help` has.
#   check_man_pages.sh TOCDLAB MAN_PAGE.1.gz
set -euo pipefail
bin=$1 page=$2
man=$(gzip -dc "$page")
grep -q '^\.SH NAME' <<<"$man" || { echo "check_man_pages: $page has no NAME section" >&2; exit 1; }
if grep -q '???' <<<"$man"; then
  echo "check_man_pages: $page has '???' (help2man in a non-UTF-8 locale)" >&2
  exit 1
fi
failures=0 commands=0 options=0

# The roff lines of the subsection .SS "TITLE", up to the next .SS or .SH.
subsection() { awk -v want=".SS \"$1\"" '$0 == want { on = 1; next } /^\.S[SH] / { on = 0 } on' <<<"$man"; }

check() {  # check WORDS...: the command `tocdlab WORDS...`
  local help section opt
  help=$("$bin" "$@" --help)
  commands=$((commands + 1))
  section=$(subsection "tocdlab $* options:")
  if [ -z "$section" ]; then
    echo "check_man_pages: no subsection 'tocdlab $* options:'" >&2
    failures=$((failures + 1))
  fi
  # Option names: the dash words before the first space of each option line of --help.
  for opt in $(awk '/^[A-Za-z].*:$/ { on = ($0 == "Options:"); next }
                    on && /^  +-/ { sub(/^ +/, ""); sub(/ .*/, ""); gsub(/,/, " "); print }' <<<"$help"); do
    options=$((options + 1))
    if ! grep -qF -- "${opt//-/\\-}" <<<"$section"; then
      echo "check_man_pages: tocdlab $* $opt is not in its man page subsection" >&2
      failures=$((failures + 1))
    fi
  done
  local sub
  for sub in $(awk '/^[A-Za-z].*:$/ { on = ($0 == "Subcommands:"); next } on && /^  +[a-z]/ { print $1 }' <<<"$help"); do
    check "$@" "$sub"
  done
}

top=$("$bin" --help)
for sub in $(awk '/^[A-Za-z].*:$/ { on = ($0 == "Subcommands:"); next } on && /^  +[a-z]/ { print $1 }' <<<"$top"); do
  check "$sub"
done
echo "check_man_pages: $commands subcommands, $options options checked, $failures missing"
[ "$failures" -eq 0 ] && [ "$commands" -gt 10 ]
