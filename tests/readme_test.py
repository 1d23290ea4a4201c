#!/usr/bin/python3
"""Runs every command line and code block of README.md as written, as doctest does for
docstrings, so that the manual cannot drift from the program.

Fenced blocks are taken by their language:

- ``sh``/``bash``/``shell``: each command line (a trailing backslash continues it; blank lines
  and ``#`` comments are skipped) runs in one bash process, in order, so an ``export`` carries
  to the next line. A line that exits non-zero fails the test, naming README.md's line.
- ``python``: the block runs with this interpreter (Debian's /usr/bin/python3) and
  ``PYTHONPATH=<binary dir>/python``, where the build puts the ``impactid`` extension. When
  ``import impactid`` fails the test fails with that message, unless the environment sets
  ``IMPACTID_README_SKIP_PYTHON=1`` (then the block is reported as skipped).
- A block of any other language (or none) cannot run, and is an error unless marked.

A block that must not run here is marked by an HTML comment on the line before its fence:
``<!-- readme-test: skip (REASON) -->``. The reason is required. The project's commands of a
skipped shell block must still exist and be executable (the set-up commands scripts/main and
scripts/test: the first takes minutes, the second runs this test); another program (srun,
mpirun) is looked up on PATH, and reported as unchecked, not failed, where this machine lacks
it: Slurm is no requirement of the tests (``--missing PROGRAM`` makes the test treat one as
missing).

The blocks run from a temporary copy of the repository root: every top-level entry is a
symbolic link to the source tree, except ``results/`` (an empty folder, so that what the blocks
write lands there and disappears with the copy) and ``build/`` (a link to the binary dir under
test). The binary dir's ``study/`` is first on PATH, so ``impactid`` is the program under test.
"""

import argparse
import os
import re
import shutil
import subprocess
import sys
import tempfile

SKIP = re.compile(r"^<!--\s*readme-test:\s*skip\s*\((?P<reason>.*)\)\s*-->\s*$")
MARKER = re.compile(r"^<!--\s*readme-test\b")
FENCE = re.compile(r"^(?P<fence>```+)\s*(?P<lang>[\w+-]*)\s*$")
SHELLS = {"sh", "bash", "shell"}
BLOCK_SECONDS = 120
NAME = "README.md"  # the file under test, as messages name it


class Block:
    def __init__(self, lang, line, text, skip_reason):
        self.lang = lang  # "" when the fence names none
        self.line = line  # README.md's line of the opening fence (1-based)
        self.text = text  # the lines between the fences
        self.skip_reason = skip_reason  # None: run it

    def where(self):
        return f"{NAME}:{self.line}"


def parse_blocks(path):
    """The fenced blocks of a Markdown file, each with the skip marker before it, if any."""
    with open(path, encoding="utf-8") as f:
        lines = f.read().split("\n")
    blocks, errors = [], []
    pending_skip = None  # (line, reason) of a marker waiting for its fence
    i = 0
    while i < len(lines):
        line = lines[i]
        fence = FENCE.match(line)
        if MARKER.match(line.strip()):
            # A marker that is malformed or gives no reason is an error, and its block is still
            # not run: it was meant to be skipped (it may be a set-up command that takes minutes).
            match = SKIP.match(line.strip())
            reason = match.group("reason").strip() if match else ""
            if not match:
                errors.append(f"{NAME}:{i + 1}: a readme-test marker must read "
                              f"'<!-- readme-test: skip (REASON) -->': {line.strip()}")
            elif not reason:
                errors.append(f"{NAME}:{i + 1}: a skip needs its reason in the parentheses")
            pending_skip = (i + 1, reason or "no valid reason")
            i += 1
            continue
        if fence:
            start = i
            end = i + 1
            while end < len(lines) and lines[end].strip() != fence.group("fence"):
                end += 1
            if end == len(lines):
                errors.append(f"{NAME}:{start + 1}: the block never closes")
                break
            reason = None
            if pending_skip is not None:
                if pending_skip[0] == start:  # the marker is the line right before the fence
                    reason = pending_skip[1]
                else:
                    errors.append(f"{NAME}:{pending_skip[0]}: a skip marker must be the line "
                                  "right before the block it skips")
                pending_skip = None
            blocks.append(Block(fence.group("lang").lower(), start + 1,
                                lines[start + 1:end], reason))
            i = end + 1
            continue
        if pending_skip is not None and line.strip():
            errors.append(f"{NAME}:{pending_skip[0]}: a skip marker must be the line right "
                          "before the block it skips")
            pending_skip = None
        i += 1
    if pending_skip is not None:
        errors.append(f"{NAME}:{pending_skip[0]}: a skip marker with no block after it")
    return blocks, errors


def command_lines(block):
    """The block's commands as (README line, text), a trailing backslash joining lines."""
    commands, current, first = [], "", None
    for offset, raw in enumerate(block.text):
        line = raw.rstrip()
        number = block.line + 1 + offset
        if not current and (not line.strip() or line.lstrip().startswith("#")):
            continue
        if first is None:
            first = number
        if line.endswith("\\"):
            current += line[:-1] + " "
            continue
        commands.append((first, current + line))
        current, first = "", None
    if current:
        commands.append((first, current))
    return commands


def check_skipped_shell(block, source_dir, missing=()):
    """A skipped shell block's commands of the project must exist and be executable. Another
    program (srun, mpirun) may be one this machine does not have: it is checked when it is on
    PATH, and reported as unchecked, not failed, when it is not."""
    errors = []
    for number, command in command_lines(block):
        program = command.split()[0]
        if "/" in program:
            path = os.path.join(source_dir, program)
            if not (os.path.isfile(path) and os.access(path, os.X_OK)):
                errors.append(f"{NAME}:{number}: {program}: skipped ({block.skip_reason}), "
                              "but no executable file of that name exists")
        elif program in missing or shutil.which(program) is None:
            print(f"--- {NAME}:{number}: {program} is not installed here: not checked")
    return errors


def run_shell(block, workspace, env):
    script = ["set -uo pipefail"]
    for number, command in command_lines(block):
        shown = command.replace("'", "'\\''")
        script.append(f"echo '$ {shown}' >&2")
        script.append(f"{command}\n__status=$?; if [ $__status -ne 0 ]; then "
                      f"echo '{NAME}:{number}: exit status '$__status': {shown}' >&2; "
                      "exit 1; fi")
    return run(["bash", "-c", "\n".join(script)], block, workspace, env)


def run_python(block, workspace, env):
    # Blank lines before the code, so that a traceback's line numbers are README.md's.
    code = "\n" * block.line + "\n".join(block.text)
    return run([sys.executable, "-c", code], block, workspace, env)


def run(argv, block, workspace, env):
    print(f"--- {block.where()}: {block.lang} block", flush=True)
    try:
        result = subprocess.run(argv, cwd=workspace, env=env, timeout=BLOCK_SECONDS)
    except subprocess.TimeoutExpired:
        return [f"{block.where()}: the block took more than {BLOCK_SECONDS} s"]
    if result.returncode != 0:
        return [f"{block.where()}: the {block.lang} block failed (exit status "
                f"{result.returncode}; its output is above)"]
    return []


def python_extension_missing(env):
    """The error of `import impactid`, or None when it imports."""
    result = subprocess.run([sys.executable, "-c", "import impactid"], env=env,
                            capture_output=True, text=True)
    if result.returncode == 0:
        return None
    return (result.stderr.strip().splitlines() or ["(no message)"])[-1]


def make_workspace(source_dir, binary_dir):
    """A temporary repository root: links to the source tree, an empty results/, build/ ->
    the binary dir."""
    workspace = tempfile.mkdtemp(prefix="impactid-readme-")
    for entry in os.listdir(source_dir):
        if entry in ("results", "build"):
            continue
        os.symlink(os.path.join(source_dir, entry), os.path.join(workspace, entry))
    os.mkdir(os.path.join(workspace, "results"))
    os.symlink(binary_dir, os.path.join(workspace, "build"))
    return workspace


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--source-dir", required=True, help="the repository root")
    parser.add_argument("--binary-dir", required=True,
                        help="the build under test: BINARY_DIR/study/impactid, BINARY_DIR/python")
    parser.add_argument("--readme", help="default: SOURCE_DIR/README.md")
    parser.add_argument("--missing", action="append", default=[], metavar="PROGRAM",
                        help="treat PROGRAM as not installed (a machine without Slurm)")
    args = parser.parse_args()
    source_dir = os.path.abspath(args.source_dir)
    binary_dir = os.path.abspath(args.binary_dir)
    readme = args.readme or os.path.join(source_dir, "README.md")
    global NAME
    NAME = os.path.basename(readme)
    if not os.access(os.path.join(binary_dir, "study", "impactid"), os.X_OK):
        print(f"readme_test: {binary_dir}/study/impactid: not built", file=sys.stderr)
        return 1

    blocks, errors = parse_blocks(readme)
    env = dict(os.environ)
    env["PATH"] = os.path.join(binary_dir, "study") + os.pathsep + env.get("PATH", "")
    python_path = os.path.join(binary_dir, "python")
    env["PYTHONPATH"] = python_path + (os.pathsep + env["PYTHONPATH"]
                                       if env.get("PYTHONPATH") else "")
    skip_python = os.environ.get("IMPACTID_README_SKIP_PYTHON") == "1"

    workspace = make_workspace(source_dir, binary_dir)
    ran = skipped = 0
    try:
        for block in blocks:
            if block.skip_reason is not None:
                skipped += 1
                print(f"--- {block.where()}: skipped ({block.skip_reason})")
                if block.lang in SHELLS:
                    errors += check_skipped_shell(block, source_dir, args.missing)
                continue
            if block.lang in SHELLS:
                errors += run_shell(block, workspace, env)
                ran += 1
            elif block.lang == "python":
                missing = python_extension_missing(env)
                if missing is None:
                    errors += run_python(block, workspace, env)
                    ran += 1
                elif skip_python:
                    skipped += 1
                    print(f"--- {block.where()}: python block skipped: IMPACTID_README_SKIP_PYTHON=1 "
                          f"and `import impactid` fails ({missing})")
                else:
                    errors.append(f"{block.where()}: `import impactid` fails with "
                                  f"PYTHONPATH={python_path}: {missing}. Build the extension "
                                  "(python/), or set IMPACTID_README_SKIP_PYTHON=1 to skip the "
                                  "Python blocks")
            else:
                errors.append(f"{block.where()}: a block in '{block.lang or 'no language'}' "
                              "cannot run; write it as sh or python, or mark it "
                              "'<!-- readme-test: skip (REASON) -->'")
    finally:
        shutil.rmtree(workspace, ignore_errors=True)

    print(f"readme_test: {ran} blocks ran, {skipped} skipped, {len(errors)} problems")
    for error in errors:
        print(error, file=sys.stderr)
    return 1 if errors else 0


if __name__ == "__main__":
    sys.exit(main())
