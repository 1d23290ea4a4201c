#!/usr/bin/env python3
"""Every file path that the documents and comments name exists: a mention `dir/file.ext` in a
tracked *.md file, or in a comment of a *.hpp, *.cpp or *.py file (a docstring too), whose first
folder is one of the repository's own (core/, study/, tests/, docs/, …) must name a file of the
repository, from its root or from the mentioning file's folder (a Markdown link), or one that
CMake configures from a tracked FILE.in (study/version.hpp). Documentation that names files the
code no longer has is an anti-pattern of docs/style.md; this catches a file moved or renamed
without its mentions.

Not checked: what runs write (anything under results/, and *.h5, *.png, … anywhere: OUTPUTS),
paths with wildcards (core/*.cpp), placeholders in capitals (plans/PLAN.toml), the build
folder, system and third-party headers (#include <…>), string literals in code (a test's
temporary plans/x.toml), and the paths of NOT_HERE below (examples, other projects' files).

    python3 tests/doc_paths_test.py [REPOSITORY]    (default: this file's repository)
"""

import os
import re
import subprocess
import sys
from pathlib import Path

SOURCES = (".md", ".hpp", ".cpp", ".py")
# What runs and builds write, named where the documents say where to find them.
OUTPUTS = {"h5", "png", "pdf", "log", "svg", "o"}
OUTPUT_FOLDERS = {"results"}
# A path: folders and a file name with an extension, not inside a longer path or a URL.
MENTION = re.compile(r"(?<![\w./\\:@~$-])((?:[\w.-]+/)+[\w.-]*\w\.[A-Za-z][A-Za-z0-9]*)(?![\w/*{<])")
# A line whose paths are not this repository's: system and third-party includes.
FOREIGN_LINE = re.compile(r"^\s*#\s*include\s*<")
# Paths that name no file of this repository, by the file that shows them: a name in an example,
# another project's file.
NOT_HERE = {"plans/README.md": {"plans/x.toml"},
            "docs/style.md": {"tests/unit/linalg/test_ode2.cpp"}}  # MFEM's


def commented_lines(name, text):
    """(line number, text to check) of a file: every line of a Markdown file; the comments of C++
    (// and /* */) and of Python (# and docstrings) otherwise."""
    lines = text.splitlines()
    if name.endswith(".md"):
        yield from enumerate(lines, 1)
        return
    in_block = False
    for number, line in enumerate(lines, 1):
        if name.endswith(".py"):
            quotes = line.count('"""') + line.count("'''")
            if in_block or quotes:
                yield number, line
            elif "#" in line:
                yield number, line[line.index("#"):]
            if quotes % 2:
                in_block = not in_block
            continue
        if in_block:
            yield number, line
            if "*/" in line:
                in_block = False
            continue
        if "//" in line:
            yield number, line[line.index("//"):]
        elif "/*" in line:
            yield number, line[line.index("/*"):]
            in_block = "*/" not in line


def tracked_files(root):
    """The repository's files: git's list, or outside a git checkout (a source archive) every file
    but those of build folders."""
    try:
        out = subprocess.run(["git", "-C", str(root), "ls-files"], capture_output=True, text=True, check=True)
        return [line for line in out.stdout.splitlines() if line]
    except (OSError, subprocess.CalledProcessError):
        files = []
        for folder, dirs, names in os.walk(root):
            dirs[:] = [d for d in dirs if not d.startswith(("build", "."))]
            files += [os.path.relpath(os.path.join(folder, n), root) for n in names]
        return files


def main():
    root = Path(sys.argv[1] if len(sys.argv) > 1 else Path(__file__).resolve().parent.parent).resolve()
    files = tracked_files(root)
    tops = {f.split("/", 1)[0] for f in files if "/" in f}
    existing = set(files)
    bad = []
    for name in files:
        if not name.endswith(SOURCES) or name == "tests/doc_paths_test.py":
            continue
        path = root / name
        try:
            text = path.read_text(encoding="utf-8")
        except (OSError, UnicodeDecodeError):
            continue
        folder = str(Path(name).parent)
        for number, line in commented_lines(name, text):
            if FOREIGN_LINE.match(line):
                continue
            for match in MENTION.finditer(line):
                mention = match.group(1)
                if mention.startswith("./"):
                    mention = mention[2:]
                if mention.startswith("../"):  # a Markdown link up from the file's folder
                    up = os.path.normpath(os.path.join(folder, mention))
                    if up.split("/", 1)[0] in tops:
                        mention = up
                first = mention.split("/", 1)[0]
                stem = mention.rsplit("/", 1)[-1].split(".", 1)[0]
                if first not in tops or first in OUTPUT_FOLDERS or mention.rsplit(".", 1)[-1] in OUTPUTS:
                    continue
                if stem.isupper() or mention in NOT_HERE.get(name, ()):
                    continue
                relative = str(Path(folder) / mention) if folder != "." else mention
                if {mention, relative, mention + ".in"} & existing:
                    continue
                bad.append(f"{name}:{number}: {mention}")
    if bad:
        print(f"doc_paths_test: {len(bad)} mention(s) of files that do not exist:")
        print("\n".join(bad))
        return 1
    print(f"doc_paths_test: every file path mentioned in {sum(f.endswith(SOURCES) for f in files)} files exists")
    return 0


if __name__ == "__main__":
    sys.exit(main())
