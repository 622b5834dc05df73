#!/usr/bin/env python3
"""Run every tocdlab / tocdlab-gui command the documentation shows, as written.

Usage:
  run_documented_commands.py --source-dir SRC --bin-dir DIR [--gui-bin-dir DIR]
                             --work-dir DIR [--select short|long|all] [FILE ...]
  run_documented_commands.py --source-dir SRC --list [FILE ...]
  run_documented_commands.py --source-dir SRC --check-links [FILE ...]
  run_documented_commands.py --check-installed-links PREFIX

Without FILE arguments the documented set is used: README.md, docs/*.md,
docs/instruments/*.md, examples/ (README.md and the comments of its data files) and the
comments of protocols/*.toml.

Where a command is found:
  * in Markdown, every line of a fenced (``` or ~~~) or indented code block that starts with a
    tocdlab invocation, backslash continuations joined, and every inline code span (also one
    broken across lines) that starts with one and is a complete command (below);
  * in TOML and CSV files, a comment that holds a tocdlab invocation (from there to the end of
    the line).
A tocdlab invocation is `tocdlab`, `tocdlab-gui` or a path ending in bin/tocdlab[-gui] (the
README's ./build/release/bin/...), after optional VAR=value assignments. A first word that is
neither an option nor one of tocdlab's subcommands makes the line prose or program output
(docs/building.md quotes a message that starts with "tocdlab needs ...").

What is not a command (the line is listed as skipped, with the reason):
  * a synopsis: placeholder syntax <NAME>, [optional ...], a|b alternatives, "...", or an
    upper-case metavariable (FILE, DIR, ID, N, LAB.toml, PROTOCOL.toml);
  * an inline span that names no file and gives fewer than two options with values: that is
    prose naming a command or an option (`tocdlab compare --material fitted` in a sentence);
    a span that names a file (demo.db, examples/...) or a redirection, or sets two options, is
    meant to be typed and runs;
  * a code line that installs and builds first and runs tocdlab after `&&` (the README's
    set-up line): the test runs on a build;
  * a command of a program this build leaves out (tocdlab-gui, tocdlab plot without Qt);
  * the explicit EXCLUSIONS below, each for something this machine does not have.

How a command runs: `bash -o pipefail -c COMMAND` in one scratch directory per document (so a
later command finds what an earlier one wrote, as a reader following the page would), with
examples/ and protocols/ of the source tree linked in, tocdlab's build first on PATH, any
`[./]build/<preset>/bin/` path replaced by the build's binaries, no display (DISPLAY and
WAYLAND_DISPLAY unset: the docs promise these commands work without one) and the caches and
settings in the work directory instead of the user's home. A non-zero exit fails the test
with file:line, the command, its exit status and the last lines of its stderr; the later
commands of that document still run (each failure is reported), those of other documents too.

Short and long: documents whose commands together take more than about a minute on a
two-core machine are listed in LONG_DOCS with their measured time; --select short runs the
others (ctest's default docs test), --select long runs those (label physics-long).
"""

import argparse
import os
import re
import shutil
import signal
import subprocess
import sys
import time
from pathlib import Path

# Each entry: (regular expression searched in the command, reason). Only what cannot run on a
# build machine belongs here; everything else runs.
EXCLUSIONS = [
    (r"--lab\s+\S*real-rig\.toml",
     "needs the real rig of examples/lab/real-rig.toml (tester at its LAN address, /dev/ttyUSB0, USB power meter)"),
    (r"--lab\s+lab\.toml",
     "needs the reader's own lab.toml with real instruments"),
    (r"^\s*(mpirun|mpiexec|srun|sbatch)\b",
     "MPI launcher for a cluster (ranks across hosts, 10^8 photons)"),
    (r"(^|[\s/])tocdlab-gui\s*(#.*)?$",
     "opens the interactive window (no --screenshot): nothing to check without a person"),
    (r"^\s*apt(-get)?\s",
     "installs a package as root"),
]

# Documents whose commands together take more than about a minute here (dev build, 2 cores,
# a cold sample cache), with the reason; they run in the physics-long test. A document in the
# list must exist and must have commands, so the list cannot go stale silently. Times measured
# on a loaded two-core machine (load average 10): demo 620 s with a cold sample cache, study
# paper at 10^5 photons 55 s, fit --method fe 114 s; the short documents took 181 s together.
LONG_DOCS = {
    "README.md": "tocdlab-gui --demo runs the demo protocol and predicts all seven steps (minutes)",
    "docs/gui.md": "tocdlab-gui --demo (twice) runs the demo protocol and predicts all seven steps (minutes)",
    "docs/packaging.md": "tocdlab demo: the demo protocol with seven FE + Monte Carlo predictions (minutes)",
    "docs/plot.md": "the demo (10 min cold), study paper at 10^5 photons (1 min), fit --method fe (2 min), "
                    "study sensitivity at 10^5 photons",
    "docs/fe.md": "tocdlab demo, fit --method fe, then compare --material fitted re-predicts every step at 10^5 photons",
    "docs/study.md": "study paper at 10^7 photons (about 20 minutes on two idle cores), the demo, "
                     "sensitivity at 10^6 photons (7.5 minutes), compare --material fitted",
    "docs/water.md": "tocdlab demo, then compare --optics water (biphasic FE and Monte Carlo per time point)",
    "docs/identify.md": "a simulated run (1 min with a cold sample cache), then identify with the optics' "
                        "Monte Carlo (2 min)",
}

PROGRAM = r"(?:(?:\./)?(?:[\w.+-]+/)*bin/)?tocdlab(?:-gui)?"
ENV_ASSIGN = r"(?:[A-Za-z_][A-Za-z0-9_]*=\S*\s+)*"
INVOCATION = re.compile(r"^\s*" + ENV_ASSIGN + "(" + PROGRAM + r")(?=\s|$)")
LAUNCHED = re.compile(r"^\s*(mpirun|mpiexec|srun|sbatch)\b.*\btocdlab")
BUILD_BIN = re.compile(r"(?<![\w/.])(?:\./)?build/[\w.+-]+/bin/(?=tocdlab)")

# Subcommands when no binary is at hand (--list, --check-links); with --bin-dir the list comes
# from `tocdlab --help` so a new command is recognised without an edit here.
DEFAULT_SUBCOMMANDS = {"compare", "db", "demo", "devices", "export", "fe", "fit", "identify", "mc", "plot",
                       "powermeter", "predict", "run", "runs", "simlab", "study", "version"}


class Command:
    def __init__(self, path, line, text, origin):
        self.path = path          # document, relative to the source tree
        self.line = line          # 1-based line of the command's first line
        self.text = text          # as written (continuations joined)
        self.origin = origin      # "block", "inline" or "comment"
        self.skip = None          # reason when it is not run

    def where(self):
        return f"{self.path}:{self.line}"


def placeholder(text):
    """Why text is a synopsis rather than a command, or None."""
    body = re.sub(r"\s#.*$", "", text)  # a trailing shell comment may say anything
    if re.search(r"<[A-Za-z][^>]*>", body):
        return "<placeholder>"
    if re.search(r"\[[^\]]*\]", body):
        return "[optional part]"
    if "..." in body or "\u2026" in body:
        return "..."
    if re.search(r"[\w-]\\?\|[\w-]", body):
        return "a|b alternatives"
    for token in body.split()[1:]:
        value = token.split("=", 1)[-1] if token.startswith("--") else token
        if re.fullmatch(r"[A-Z][A-Z0-9_]*(\.[a-z]+)?", value.strip("\"'(),")):
            return "upper-case metavariable " + value
    return None


def names_a_file(text):
    for token in text.split()[1:]:
        if token in (">", ">>", "<", "|") or token.startswith(">"):
            return True
        if token.startswith("-"):
            continue
        if "/" in token or re.search(r"\.[A-Za-z]{1,5}$", token):
            return True
    return False


def options_with_values(text):
    tokens = text.split()[1:]
    count = 0
    for i, token in enumerate(tokens):
        if token.startswith("--") and "=" in token:
            count += 1
        elif token.startswith("-") and i + 1 < len(tokens) and not tokens[i + 1].startswith("-"):
            count += 1
    return count


def first_argument_is_command(text, subcommands):
    match = INVOCATION.match(text)
    rest = text[match.end():].split()
    if match.group(1).endswith("-gui"):
        return True
    if not rest:
        return True
    return rest[0].startswith("-") or rest[0] in subcommands


def markdown_commands(path, rel, subcommands):
    lines = path.read_text(encoding="utf-8").split("\n")
    commands = []
    fence = None
    prose = []  # (line number, text) of the current paragraph, for inline spans
    previous_blank = True

    def flush_prose():
        if not prose:
            return
        joined = ""
        starts = []  # offset in joined -> line number
        for number, text in prose:
            starts.append((len(joined), number))
            joined += text + " "
        for match in re.finditer(r"(`+)(.+?)\1", joined):
            span = match.group(2).strip()
            if not INVOCATION.match(span) or not first_argument_is_command(span, subcommands):
                continue
            number = [n for offset, n in starts if offset <= match.start()][-1]
            command = Command(rel, number, span, "inline")
            reason = placeholder(span)
            if reason:
                command.skip = "synopsis (" + reason.split(" ")[0] + ")"
            elif not names_a_file(span) and options_with_values(span) < 2:
                command.skip = "prose naming a command or option"
            commands.append(command)
        prose.clear()

    i = 0
    while i < len(lines):
        line = lines[i]
        stripped = line.strip()
        if fence is None and re.match(r"^\s*(```|~~~)", line):
            flush_prose()
            fence = stripped[:3]
            i += 1
            continue
        if fence is not None:
            if stripped.startswith(fence):
                fence = None
                i += 1
                continue
            i = code_line(lines, i, rel, commands, subcommands)
            continue
        indented = line.startswith("    ") and stripped and (previous_blank or in_indented_block(lines, i))
        if indented and not prose:
            i = code_line(lines, i, rel, commands, subcommands)
            previous_blank = False
            continue
        if not stripped:
            flush_prose()
            previous_blank = True
        else:
            prose.append((i + 1, line))
            previous_blank = False
        i += 1
    flush_prose()
    return commands


def in_indented_block(lines, i):
    # An indented line continues a code block when the block above it is indented code.
    j = i - 1
    while j >= 0 and lines[j].startswith("    ") and lines[j].strip():
        j -= 1
    return j >= 0 and not lines[j].strip() and j < i - 1


def code_line(lines, i, rel, commands, subcommands):
    """Read the (possibly continued) code line at i; record it when it is a command."""
    number = i + 1
    text = lines[i].strip()
    while text.endswith("\\") and i + 1 < len(lines):
        i += 1
        text = text[:-1].rstrip() + " " + lines[i].strip()
    text = re.sub(r"^\$\s+", "", text)
    if INVOCATION.match(text) and first_argument_is_command(text, subcommands):
        command = Command(rel, number, text, "block")
        reason = placeholder(text)
        if reason:
            command.skip = "synopsis (" + reason.split(" ")[0] + ")"
        commands.append(command)
    elif LAUNCHED.match(text):
        commands.append(Command(rel, number, text, "block"))
    elif re.search(r"(&&|;)\s*" + ENV_ASSIGN + PROGRAM + r"(\s|$)", text):
        # The README's set-up line: install, configure, build, then tocdlab. The test runs on a
        # build that exists already; installing packages and building are not its to do.
        command = Command(rel, number, text, "block")
        command.skip = "set-up line (installs packages and builds before tocdlab runs)"
        commands.append(command)
    return i + 1


def comment_commands(path, rel, subcommands):
    commands = []
    for number, line in enumerate(path.read_text(encoding="utf-8").split("\n"), 1):
        comment = re.match(r"^\s*#(.*)$", line) or re.search(r"\s#(.*)$", line)
        if not comment:
            continue
        found = re.search(r"(?<![\w`-])" + PROGRAM + r"\s.*$", comment.group(1))
        if not found:
            continue
        text = found.group(0).strip()
        if not first_argument_is_command(text, subcommands):
            continue
        command = Command(rel, number, text, "comment")
        reason = placeholder(text)
        if reason:
            command.skip = "synopsis (" + reason.split(" ")[0] + ")"
        commands.append(command)
    return commands


def documented_files(source):
    files = [source / "README.md"]
    files += sorted((source / "docs").glob("*.md"))
    files += sorted((source / "docs" / "instruments").glob("*.md"))
    files += sorted(p for p in (source / "examples").rglob("*")
                    if p.is_file() and p.suffix in (".md", ".toml", ".csv"))
    files += sorted((source / "protocols").glob("*.toml"))
    return files


def extract(paths, source, subcommands, built=None):
    """The commands of paths. built: (tocdlab's subcommands in this build, whether tocdlab-gui
    is built), or None to take every command as built (--list)."""
    commands = []
    for path in paths:
        try:
            rel = str(path.resolve().relative_to(source.resolve()))
        except ValueError:
            rel = str(path)
        if path.suffix == ".md":
            found = markdown_commands(path, rel, subcommands)
        else:
            found = comment_commands(path, rel, subcommands)
        for command in found:
            if command.skip is None and built is not None:
                # A build without the GUI or plot (TOCD_WITH_GUI/PLOT=OFF, the sanitize preset)
                # cannot run their commands; they are counted, not failed.
                match = INVOCATION.match(command.text)
                words = command.text[match.end():].split() if match else []
                if match and match.group(1).endswith("-gui") and not built[1]:
                    command.skip = "not in this build: tocdlab-gui"
                elif match and words and words[0] in subcommands and words[0] not in built[0]:
                    command.skip = "not in this build: tocdlab " + words[0]
            if command.skip is None:
                for pattern, reason in EXCLUSIONS:
                    if re.search(pattern, command.text):
                        command.skip = "excluded: " + reason
                        break
        commands += found
    return commands


def subcommands_of(bin_dir):
    try:
        out = subprocess.run([str(bin_dir / "tocdlab"), "--help"], capture_output=True, text=True,
                             timeout=60).stdout
    except (OSError, subprocess.TimeoutExpired):
        return DEFAULT_SUBCOMMANDS
    names = set()
    in_list = False
    for line in out.splitlines():
        if line.startswith("Subcommands:"):
            in_list = True
        elif in_list and re.match(r"^\s+([a-z][\w-]*)\s", line):
            names.add(line.split()[0])
    return names or DEFAULT_SUBCOMMANDS


def prepare_scratch(scratch, source):
    if scratch.exists():
        shutil.rmtree(scratch)
    scratch.mkdir(parents=True)
    for name in ("examples", "protocols"):
        (scratch / name).symlink_to(source / name)


def run_commands(commands, args, source):
    bin_dir = Path(args.bin_dir).resolve()
    gui_dir = Path(args.gui_bin_dir).resolve() if args.gui_bin_dir else bin_dir
    work = Path(args.work_dir).resolve()
    work.mkdir(parents=True, exist_ok=True)
    env = dict(os.environ)
    env.pop("DISPLAY", None)
    env.pop("WAYLAND_DISPLAY", None)
    env["PATH"] = os.pathsep.join(dict.fromkeys([str(bin_dir), str(gui_dir), env.get("PATH", "")]))
    # The demo's sample cache and the window's settings: in the work directory, kept between
    # runs of the test (deleting it is always safe, docs/demo.md), never the user's.
    env["XDG_CACHE_HOME"] = str(work / "cache")
    env["XDG_CONFIG_HOME"] = str(work / "config")
    env.pop("TOCDLAB_CACHE_DIR", None)

    failures = []
    ran = 0
    by_doc = {}
    for command in commands:
        by_doc.setdefault(command.path, []).append(command)
    for doc, doc_commands in by_doc.items():
        runnable = [c for c in doc_commands if c.skip is None]
        if not runnable:
            continue
        scratch = work / re.sub(r"[^\w.-]", "_", doc)
        prepare_scratch(scratch, source)
        doc_start = time.monotonic()
        for command in runnable:
            text = BUILD_BIN.sub(lambda m: (str(gui_dir) if "-gui" in command.text[m.end():m.end() + 11]
                                            else str(bin_dir)) + "/", command.text)
            start = time.monotonic()
            try:
                result = subprocess.run(["bash", "-o", "pipefail", "-c", text], cwd=scratch, env=env,
                                        stdin=subprocess.DEVNULL, capture_output=True, text=True,
                                        errors="replace", timeout=args.timeout)
                status, stderr = result.returncode, result.stderr
                if status < 0:  # bash exec'd the program, which a signal ended
                    status = f"{status} (killed by signal {signal.Signals(-status).name})"
                # Kept beside what the command wrote, for a person checking the numbers a page
                # quotes (hidden, so no documented command sees them in a listing).
                (scratch / f".line{command.line}.stdout").write_text(result.stdout)
                (scratch / f".line{command.line}.stderr").write_text(result.stderr)
            except subprocess.TimeoutExpired as expired:
                status = "timeout after %d s" % args.timeout
                stderr = expired.stderr.decode(errors="replace") if expired.stderr else ""
            seconds = time.monotonic() - start
            ran += 1
            if status == 0:
                print(f"ok    {seconds:7.1f} s  {command.where()}: {command.text}", flush=True)
                continue
            tail = "\n".join("      | " + l for l in stderr.rstrip().splitlines()[-args.tail:])
            failures.append(command)
            print(f"FAIL  {seconds:7.1f} s  {command.where()}: {command.text}", flush=True)
            print(f"{command.where()}: documented command failed (exit status {status}):\n"
                  f"      $ {command.text}\n{tail}", file=sys.stderr, flush=True)
        print(f"      {time.monotonic() - doc_start:7.1f} s  {doc} (all of its commands)", flush=True)
    return ran, failures


def select(commands, which):
    if which == "all":
        return commands
    long = which == "long"
    return [c for c in commands if (c.path in LONG_DOCS) == long]


def summary(commands, ran, failures, which):
    skipped = {}
    for command in commands:
        if command.skip:
            skipped.setdefault(command.skip, []).append(command)
    print(f"documented commands ({which}): {len(commands)} found, {ran} run, "
          f"{len(failures)} failed, {sum(len(v) for v in skipped.values())} skipped")
    for reason, items in sorted(skipped.items()):
        print(f"  skipped {len(items):3d}: {reason}")


def check_links(paths, source):
    """Every relative link of the Markdown files points at a file of the source tree."""
    broken = []
    for path in paths:
        if path.suffix != ".md":
            continue
        broken += broken_links(path, path.read_text(encoding="utf-8"))
    for where, target in broken:
        print(f"{where}: link to a missing file: {target}", file=sys.stderr)
    print(f"links checked in {sum(1 for p in paths if p.suffix == '.md')} files, {len(broken)} broken")
    return 1 if broken else 0


def broken_links(path, text):
    broken = []
    fence = None
    for number, line in enumerate(text.split("\n"), 1):
        if re.match(r"^\s*(```|~~~)", line):
            fence = None if fence else line.strip()[:3]
            continue
        if fence or line.startswith("    "):
            continue
        for match in re.finditer(r"!?\[[^\]]*\]\(([^)\s]+)(?:\s+\"[^\"]*\")?\)", line):
            target = match.group(1)
            if re.match(r"^[a-z][a-z0-9+.-]*:", target) or target.startswith("#"):
                continue
            local = target.split("#", 1)[0]
            if local and not (path.parent / local).exists():
                broken.append((f"{path}:{number}", target))
    return broken


def check_installed_links(prefix):
    """The same check over an installed tree (cmake --install): the README and docs as they
    are laid out under PREFIX/share/doc/tocdlab and the examples under PREFIX/share/tocdlab."""
    prefix = Path(prefix)
    roots = [prefix / "share" / "doc" / "tocdlab", prefix / "share" / "tocdlab"]
    paths = sorted(p for root in roots if root.is_dir() for p in root.rglob("*.md"))
    if not paths:
        print(f"no installed Markdown under {prefix}", file=sys.stderr)
        return 1
    broken = []
    for path in paths:
        broken += broken_links(path, path.read_text(encoding="utf-8"))
    for where, target in broken:
        print(f"{where}: link to a missing file: {target}", file=sys.stderr)
    print(f"installed links checked in {len(paths)} files, {len(broken)} broken")
    return 1 if broken else 0


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--source-dir", default=str(Path(__file__).resolve().parents[2]))
    parser.add_argument("--bin-dir")
    parser.add_argument("--gui-bin-dir")
    parser.add_argument("--work-dir")
    parser.add_argument("--select", choices=("short", "long", "all"), default="all")
    parser.add_argument("--timeout", type=int, default=1800, help="seconds per command")
    parser.add_argument("--tail", type=int, default=15, help="stderr lines shown for a failure")
    parser.add_argument("--list", action="store_true", help="print the commands found, run nothing")
    parser.add_argument("--check-links", action="store_true")
    parser.add_argument("--check-installed-links", metavar="PREFIX")
    parser.add_argument("files", nargs="*")
    args = parser.parse_args()

    if args.check_installed_links:
        return check_installed_links(args.check_installed_links)
    source = Path(args.source_dir).resolve()
    paths = [Path(f).resolve() for f in args.files] if args.files else documented_files(source)
    if args.check_links:
        return check_links(paths, source)

    for doc in LONG_DOCS:
        if not (source / doc).is_file():
            print(f"LONG_DOCS names {doc}, which does not exist", file=sys.stderr)
            return 1
    built = None
    if args.bin_dir:
        gui_dir = Path(args.gui_bin_dir or args.bin_dir)
        built = (subcommands_of(Path(args.bin_dir)), (gui_dir / "tocdlab-gui").is_file())
    commands = extract(paths, source, DEFAULT_SUBCOMMANDS | (built[0] if built else set()), built)
    if not args.files:
        runnable_docs = {c.path for c in commands
                         if c.skip is None or c.skip.startswith("not in this build")}
        stale = sorted(set(LONG_DOCS) - runnable_docs)
        if stale:
            print("LONG_DOCS names documents without a runnable command: " + ", ".join(stale),
                  file=sys.stderr)
            return 1
    commands = select(commands, args.select)

    if args.list:
        for command in commands:
            state = "skip: " + command.skip if command.skip else ("long" if command.path in LONG_DOCS else "run")
            print(f"{command.where()}\t{command.origin}\t{state}\t{command.text}")
        summary(commands, 0, [], args.select)
        return 0
    if not args.bin_dir or not args.work_dir:
        parser.error("--bin-dir and --work-dir are needed to run the commands")
    ran, failures = run_commands(commands, args, source)
    summary(commands, ran, failures, args.select)
    if failures:
        print(f"{len(failures)} documented command(s) failed:", file=sys.stderr)
        for command in failures:
            print(f"  {command.where()}: {command.text}", file=sys.stderr)
        return 1
    if ran == 0 and not any(c.skip for c in commands):
        print("no documented command found", file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
