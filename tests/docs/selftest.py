#!/usr/bin/env python3
"""The docs runner judged on pages whose answer is known.

Usage: selftest.py broken|good|links RUNNER --source-dir SRC --bin-dir DIR [--gui-bin-dir DIR]
                   --work-dir DIR

  broken  a page with one good and one broken command: the runner exits 1 and names the
          broken one with file:line, its exit status, the command and tocdlab's message
  good    a page whose commands all work, beside a synopsis and a prose span that would fail
          if run, and a command that needs the file an earlier one wrote: the runner passes
  links   a page with a link to a missing file: --check-links fails and names it
"""
import subprocess
import sys
from pathlib import Path

here = Path(__file__).resolve().parent
case, runner, rest = sys.argv[1], sys.argv[2], sys.argv[3:]
work = rest[rest.index("--work-dir") + 1]
common = [a for i, a in enumerate(rest) if a != "--work-dir" and (i == 0 or rest[i - 1] != "--work-dir")]
failed = []


def run(*arguments):
    result = subprocess.run([sys.executable, runner, *arguments], capture_output=True, text=True)
    print(f"--- exit status {result.returncode}\n{result.stdout}{result.stderr}")
    return result


def expect(condition, what):
    if not condition:
        failed.append(what)
        print("FAILED: " + what, file=sys.stderr)


if case == "broken":
    result = run(*common, "--work-dir", work, str(here / "selftest" / "broken.md"))
    expect(result.returncode == 1, "the runner exits 1 on a page with a broken command")
    expect("broken.md:5: documented command failed (exit status 2)" in result.stderr,
           "the failure names the broken command's file:line and exit status")
    expect("$ tocdlab fit --csv examples/data/stress-strain.csv --no-such-option" in result.stderr,
           "the failure shows the command as written")
    expect("tocdlab: usage error:" in result.stderr, "the failure shows tocdlab's own message")
    expect("broken.md:4: documented" not in result.stderr, "the good command of that page is not blamed")
    expect("2 run, 1 failed" in result.stdout, "both commands ran, one failed")
elif case == "good":
    result = run(*common, "--work-dir", work, str(here / "selftest" / "good.md"))
    expect(result.returncode == 0, "the runner passes a page whose commands all work")
    expect("2 run, 0 failed, 2 skipped" in result.stdout,
           "two commands ran; the synopsis and the prose span were skipped")
elif case == "links":
    result = run("--check-links", str(here / "selftest" / "broken-link.md"))
    expect(result.returncode == 1, "--check-links exits 1 on a link to a missing file")
    expect("broken-link.md:3: link to a missing file: no-such-page.md" in result.stderr,
           "the broken link is named with file:line")
    expect("1 broken" in result.stdout, "only the missing file's link is broken")
else:
    sys.exit(f"selftest.py: unknown case {case}")
sys.exit(1 if failed else 0)
