#!/usr/bin/env python3
"""No source outside core/contact/ names a contact law by its value (issue 35).

A law is named elsewhere through its registry (core/contact/contact_law_registry.hpp: its name,
parameters, validation and the traits springs, explicit_force, iterates) or through
ContactPenalties' predicates (lagrange(), explicit_force()), so that adding a law touches
core/contact/ and not every layer. This test fails when a C++ source of core/, metrics/, study/,
python/ or bench/ outside core/contact/ names `ContactLaw::<value>`, except the files of ALLOWED
(none today), each with the reason it still does; and it fails when an allowed file no longer
does, so that the list cannot outlive its reasons. tests/ may name every
law: tests run each one.
"""
import pathlib
import re
import sys

TOPS = ("core", "metrics", "study", "python", "bench")
OWNER = "core/contact/"
VALUE = re.compile(r"\bContactLaw::(\w+)")

# Files that may still name a law's value, each with its reason: none. The steppers ask
# ContactPenalties' predicates, the run and the batch kernels' eligibility the registry's
# descriptors; an entry added here must say why that cannot serve.
ALLOWED: dict = {}


def main() -> int:
    root = pathlib.Path(sys.argv[1] if len(sys.argv) > 1 else ".").resolve()
    problems = []
    naming = set()
    for top in TOPS:
        for source in sorted((root / top).rglob("*")):
            if source.suffix not in (".hpp", ".cpp", ".h", ".cc"):
                continue
            name = source.relative_to(root).as_posix()
            if name.startswith(OWNER):
                continue
            text = source.read_text(encoding="utf-8")
            found = sorted({m.group(0) for m in VALUE.finditer(text)})
            if not found:
                continue
            naming.add(name)
            if name not in ALLOWED:
                lines = [str(text.count("\n", 0, m.start()) + 1) for m in VALUE.finditer(text)]
                problems.append(f"{name}:{','.join(lines)}: names {', '.join(found)}: ask the "
                                "contact-law registry (core/contact/contact_law_registry.hpp) "
                                "or ContactPenalties instead")
    for name in sorted(set(ALLOWED) - naming):
        problems.append(f"{name}: no longer names a ContactLaw value: remove it from ALLOWED "
                        "in tests/contact_law_ownership_test.py")
    for p in problems:
        print(p, file=sys.stderr)
    print(f"contact-law ownership: {len(naming)} file(s) outside {OWNER} name a law, "
          f"{len(ALLOWED)} allowed, {len(problems)} problem(s)")
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
