#!/usr/bin/env python3
"""A method's behaviour lives in its own files under core/methods/, reached through its
descriptor (core/methods/method_registry.hpp), not in branches on one method elsewhere.

Fails when a C++ source outside core/methods/ (in core/, metrics/, study/, bench/, fuzz/,
python/; tests/ test particular methods and are left out) names a MethodKind value
(`MethodKind::hht`) or tests the MethodParams variant for one method's alternative
(`std::holds_alternative<HhtParams>`, `std::get_if<HhtParams>`, `std::get<HhtParams>`). The
enumerators and alternatives are read from core/methods/method.hpp. Code that must know how a
method is stepped asks for its stepper's coefficients (core/methods/stepper_coefficients.hpp) and
dispatches on the stepper.

ALLOWED lists today's exceptions, each with its reason. It is exact: a file that no longer needs
its entry fails the test too, so the list only shrinks.
"""
import pathlib
import re
import sys

SCANNED = ["core", "metrics", "study", "bench", "fuzz", "python"]
OWNER = "core/methods/"
SUFFIXES = {".cpp", ".hpp", ".h", ".cc"}

ALLOWED = {
    "core/reference/model_reference.cpp":
        "a model's converged reference is computed with backward Euler, by its definition",
    "study/plan/simulation_settings.hpp":
        "hht is the default method of the command line and of plans",
    "study/plan/work_precision_plan.cpp":
        "the default method set of a work-precision study (the paper's five methods)",
}


def method_names(root: pathlib.Path):
    header = (root / "core/methods/method.hpp").read_text()
    enum = re.search(r"enum class MethodKind\s*{([^}]*)}", header)
    variant = re.search(r"using MethodParams\s*=\s*std::variant<([^>]*)>", header)
    if not enum or not variant:
        sys.exit("method_ownership: MethodKind or MethodParams not found in method.hpp")
    kinds = [k.strip() for k in enum.group(1).split(",") if k.strip()]
    params = [p.strip() for p in variant.group(1).split(",") if p.strip()]
    return kinds, params


def comment_free(text: str) -> str:
    """The text without // and /* */ comments (string literals are not special here)."""
    text = re.sub(r"/\*.*?\*/", " ", text, flags=re.DOTALL)
    return re.sub(r"//[^\n]*", "", text)


def main() -> int:
    root = pathlib.Path(sys.argv[1] if len(sys.argv) > 1 else ".").resolve()
    kinds, params = method_names(root)
    pattern = re.compile(
        r"\bMethodKind::(?:%s)\b|\b(?:holds_alternative|get_if|get)\s*<\s*(?:%s)\s*>"
        % ("|".join(kinds), "|".join(params)))
    offenders = {}
    for top in SCANNED:
        for path in sorted((root / top).rglob("*")):
            if path.suffix not in SUFFIXES or not path.is_file():
                continue
            rel = path.relative_to(root).as_posix()
            if rel.startswith(OWNER):
                continue
            hits = pattern.findall(comment_free(path.read_text(errors="replace")))
            if hits:
                offenders[rel] = sorted(set(hits))
    problems = []
    for rel, hits in offenders.items():
        if rel not in ALLOWED:
            problems.append(f"{rel}: names {', '.join(hits)} outside core/methods/; give the "
                            "behaviour to the method's descriptor (docs/architecture.md, "
                            "\"Adding a method\")")
    for rel in ALLOWED:
        if rel not in offenders:
            problems.append(f"{rel}: allowlisted but names no particular method any more; "
                            "remove its entry from ALLOWED")
    for p in problems:
        print("method_ownership:", p)
    print(f"method_ownership: {len(offenders)} file(s) outside core/methods/ name a method, "
          f"{len(ALLOWED)} allowlisted, {len(problems)} problem(s)")
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
