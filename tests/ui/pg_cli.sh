#!/usr/bin/env bash
# The command line on a PostgreSQL server (docs/database.md, "PostgreSQL"), run by ctest inside
# tests/db/with_pg_server (PGHOST, PGPORT, PGUSER, PGPASSWORD set):
#  1. a run recorded into a local file, pushed twice: the server holds it once, and compare,
#     export and fit print from the server what they print from the file;
#  2. three rigs at once: two record into local files and push, one records into the server
#     directly; all complete, the server's sample counts equal the files';
#  3. the server down: a run with --db on the server is refused before anything moves; a run
#     into a local file with --push-to completes, warns, and a later push succeeds.
#   pg_cli.sh TOCDLAB PROTOCOL
set -euo pipefail
tocdlab=$1
protocol=$2
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
cd "$work"
fail() { echo "pg_cli: $*" >&2; exit 1; }
json() { /usr/bin/python3 -c "import json,sys; d=json.load(open(sys.argv[1])); print($2)" "$1"; }

createdb lab
server=postgresql:///lab
run=(run "$protocol" --simulated --clock-factor 5 --no-predict)

# 1. Store and forward, twice.
"$tocdlab" "${run[@]}" --db local.db > /dev/null 2> run.err || { cat run.err; fail "run into local.db failed"; }
"$tocdlab" db push --from local.db --to "$server" --json > push1.json
"$tocdlab" db push --from local.db --to "$server" --json > push2.json 2> push2.err
[ "$(json push1.json 'd["runs"][0]["action"]')" = copied ] || fail "first push: $(cat push1.json)"
[ "$(json push2.json 'd["runs"][0]["action"]')" = unchanged ] || fail "second push: $(cat push2.json)"
grep -q "0 copied, 0 updated, 1 already there" push2.err || fail "second push said: $(cat push2.err)"
n=$(json push1.json 'd["runs"][0]["server_run_id"]')
[ "$("$tocdlab" runs --db "$server" --json | /usr/bin/python3 -c 'import json,sys; print(len(json.load(sys.stdin)["runs"]))')" = 1 ] ||
  fail "the server holds more than one run"
"$tocdlab" compare --db local.db --run 1 > compare.file
"$tocdlab" compare --db "$server" --run "$n" > compare.server
diff compare.file compare.server || fail "compare differs between the file and the server"
[ -s compare.file ] || fail "compare printed nothing"
for table in steps samples events; do
  "$tocdlab" export --db local.db --run 1 --table "$table" > "$table.file.csv"
  "$tocdlab" export --db "$server" --run "$n" --table "$table" > "$table.server.csv"
  diff -q "$table.file.csv" "$table.server.csv" > /dev/null || fail "export --table $table differs"
done
# The fit of a run's load/displacement reads the same data from either.
"$tocdlab" fit --db local.db --run 1 > fit.file 2> /dev/null
"$tocdlab" fit --db "$server" --run "$n" > fit.server 2> /dev/null
diff fit.file fit.server || fail "fit differs between the file and the server"
echo "pg_cli: 1. one run pushed twice: once on the server, compare, export and fit identical" >&2

# 2. Three rigs at once.
( "$tocdlab" "${run[@]}" --seed 2 --db rig1.db > /dev/null 2> rig1.err &&
  "$tocdlab" db push --from rig1.db --to "$server" --json > rig1.json 2>> rig1.err ) &
a=$!
( "$tocdlab" "${run[@]}" --seed 3 --db rig2.db > /dev/null 2> rig2.err &&
  "$tocdlab" db push --from rig2.db --to "$server" --json > rig2.json 2>> rig2.err ) &
b=$!
"$tocdlab" "${run[@]}" --seed 4 --db "$server" --json > rig3.json 2> rig3.err || { cat rig3.err; fail "rig 3 (direct) failed"; }
wait $a || { cat rig1.err; fail "rig 1 failed"; }
wait $b || { cat rig2.err; fail "rig 2 failed"; }
[ "$(json rig3.json 'd["state"]')" = completed ] || fail "rig 3: $(cat rig3.json)"
[ "$(json rig3.json 'd["samples_lost"]')" = 0 ] || fail "rig 3 lost samples"
for rig in rig1 rig2; do
  id=$(json $rig.json 'd["runs"][0]["server_run_id"]')
  local_n=$(($("$tocdlab" export --db $rig.db --run 1 --table samples | wc -l) - 1))
  server_n=$(($("$tocdlab" export --db "$server" --run "$id" --table samples | wc -l) - 1))
  if [ "$local_n" -le 1000 ] || [ "$local_n" != "$server_n" ]; then
    fail "$rig: $local_n samples in the file, $server_n on the server"
  fi
done
direct=$(json rig3.json 'd["run_id"]')
direct_n=$(($("$tocdlab" export --db "$server" --run "$direct" --table samples | wc -l) - 1))
[ "$direct_n" -gt 1000 ] || fail "rig 3 recorded $direct_n samples into the server"
"$tocdlab" runs --db "$server" --json > runs.json
[ "$(json runs.json 'len(d["runs"])')" = 4 ] || fail "the server lists $(json runs.json 'len(d["runs"])') runs, not 4"
[ "$(json runs.json '",".join(sorted(set(r["status"] for r in d["runs"])))')" = completed ] || fail "$(cat runs.json)"
echo "pg_cli: 2. three rigs at once: all completed, server counts equal the files' ($direct_n direct)" >&2

# 3. The server down.
down=postgresql://127.0.0.1:1/lab
if "$tocdlab" "${run[@]}" --db "$down" > down.out 2> down.err; then fail "a run into a server that is down succeeded"; fi
grep -q "cannot connect to PostgreSQL at 'postgresql://127.0.0.1:1/lab'" down.err || fail "run said: $(cat down.err)"
[ ! -s down.out ] || fail "a refused run printed on stdout"
"$tocdlab" "${run[@]}" --db later.db --push-to "$down" > /dev/null 2> later.err || { cat later.err; fail "the run with --push-to a server that is down failed"; }
grep -q "is recorded in later.db but was not pushed" later.err || fail "no warning: $(cat later.err)"
grep -q "tocdlab db push --from later.db --to postgresql://127.0.0.1:1/lab" later.err || fail "no push command: $(cat later.err)"
"$tocdlab" db push --from later.db --to "$server" --json > later.json
[ "$(json later.json 'd["runs"][0]["action"]')" = copied ] || fail "the later push: $(cat later.json)"
echo "pg_cli: 3. the server down: a direct run refused, a local run completed and pushed later" >&2
