#!/usr/bin/python3
"""`impactid plot` (study/cli/plot_command.hpp) beyond what figures/check_figures.py covers (which
plots every shipped plan's small results file): PDF as well as PNG, the files it refuses, and how
it finds Python and the figure package.

1. a small grid, a history file and a spectral file are plotted as PDF and as PNG: every file it
   names is written, non-empty, of its format;
2. a missing file, a file that is not HDF5 and an HDF5 file that is not impactid's: exit 2, the
   file named;
3. IMPACTID_PYTHON naming no program, and a Python without matplotlib: exit 1, saying what is
   missing and how to get it; IMPACTID_FIGURES_DIR naming a folder without the package: exit 1,
   naming it;
4. installed (`cmake --install BUILD --component program --prefix TMP`), the program runs the
   package installed beside it, not the source tree's;
5. installed (`--component python`), `impactid.plot` finds the package installed with it;
6. the figures' colours follow the program's method list (`impactid methods --json`): one colour
   per method, none repeated, and a different list gives different colours.

    tests/plot_command_test.py --impactid build/study/impactid --build-dir build
"""

import argparse
import json
import os
import re
import subprocess
import sys
import tempfile
from pathlib import Path

GRID = """
name = "small-grid"
[scene]
elements = 20
[method]
name = "hht"
[study]
kind = "grid"
[study.axes]
alpha = { values = [-0.3, 0.0] }
delta = { values = [0.0, 0.3, 0.6] }
[study.practical]
eps_p = 0.5
"""

SPECTRAL = """
name = "small-spectral"
[study]
kind = "spectral"
omega_dt = { from = 0.01, to = 10.0, points = 20 }
methods = [{ method = "cdm" }, { method = "hht", alpha = -0.1 }]
"""

MAGIC = {"png": b"\x89PNG\r\n\x1a\n", "pdf": b"%PDF"}


def run(cmd, cwd, env=None):
    return subprocess.run(cmd, cwd=cwd, capture_output=True, text=True, timeout=180, env=env)


def written(p):
    return [Path(m) for m in re.findall(r"^wrote (.+)$", p.stdout, re.M)]


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--impactid", required=True)
    parser.add_argument("--build-dir", required=True)
    args = parser.parse_args()
    impactid = str(Path(args.impactid).resolve())
    failures = []

    def expect(ok, what):
        if not ok:
            failures.append(what)

    with tempfile.TemporaryDirectory(prefix="plot-command-") as tmp:
        tmp = Path(tmp)
        (tmp / "grid.toml").write_text(GRID)
        p = run([impactid, "run", "grid.toml", "--output", "grid.h5"], tmp)
        expect(p.returncode == 0, f"run grid: {p.stderr}")
        p = run([impactid, "simulate", "--elements", "20", "--history", "history.h5"], tmp)
        expect(p.returncode == 0, f"simulate --history: {p.stderr}")
        (tmp / "spectral.toml").write_text(SPECTRAL)
        p = run([impactid, "run", "spectral.toml", "--output", "spectral.h5"], tmp)
        spectral = p.returncode == 0
        if not spectral:  # the spectral plan's keys are the spectral study's; say so, go on
            failures.append(f"run spectral: {p.stderr}")

        # 1. every kind as PNG and PDF
        for name in ["grid.h5", "history.h5"] + (["spectral.h5"] if spectral else []):
            for fmt in ("png", "pdf"):
                out = tmp / f"{name}-{fmt}"
                p = run([impactid, "plot", name, "--out", str(out), "--format", fmt], tmp)
                files = written(p)
                expect(p.returncode == 0 and files, f"plot {name} --format {fmt}: exit {p.returncode}\n{p.stdout}{p.stderr}")
                for f in files:
                    f = f if f.is_absolute() else tmp / f
                    data = f.read_bytes() if f.exists() else b""
                    expect(f.suffix == f".{fmt}" and data.startswith(MAGIC[fmt]) and len(data) > 10_000,
                           f"plot {name}: {f} is not a {fmt} of more than 10 kB ({len(data)} bytes)")
        # the default folder: beside the file
        p = run([impactid, "plot", "grid.h5"], tmp)
        expect(p.returncode == 0 and all(str(f).startswith(str(tmp / "grid-figures")) or
                                          str(f).startswith("grid-figures") for f in written(p)) and written(p),
               f"plot without --out: {p.stdout}{p.stderr}")

        # 2. files it refuses
        (tmp / "notes.h5").write_text("not HDF5\n")
        subprocess.run(["/usr/bin/python3", "-c", "import h5py; h5py.File('foreign.h5', 'w').attrs['format'] = 'x'"],
                       cwd=tmp, check=True)
        for name, words in (("missing.h5", "missing.h5: no such file"), ("notes.h5", "notes.h5: not a readable HDF5 file"),
                            ("foreign.h5", "format = 'x': not a file impactid writes")):
            p = run([impactid, "plot", name], tmp)
            expect(p.returncode == 2 and words in p.stderr, f"plot {name}: exit {p.returncode}, {p.stderr!r}, expected {words!r}")
        p = run([impactid, "plot", "grid.h5", "--format", "svg"], tmp)
        expect(p.returncode == 2, f"--format svg: exit {p.returncode}")

        # 3. Python and the package missing
        env = dict(os.environ, IMPACTID_PYTHON=str(tmp / "no-python"))
        p = run([impactid, "plot", "grid.h5"], tmp, env)
        expect(p.returncode == 1 and "no-python: no such program" in p.stderr and "python3-matplotlib" in p.stderr,
               f"no Python: exit {p.returncode}, {p.stderr!r}")
        bare = tmp / "bare-python"
        bare.write_text("#!/bin/sh\nexec /usr/bin/python3 -S \"$@\"\n")  # no site-packages: no matplotlib
        bare.chmod(0o755)
        p = run([impactid, "plot", "grid.h5"], tmp, dict(os.environ, IMPACTID_PYTHON=str(bare)))
        expect(p.returncode == 1 and "matplotlib (Debian: python3-matplotlib)" in p.stderr,
               f"no matplotlib: exit {p.returncode}, {p.stderr!r}")
        (tmp / "empty").mkdir()
        p = run([impactid, "plot", "grid.h5"], tmp, dict(os.environ, IMPACTID_FIGURES_DIR=str(tmp / "empty")))
        expect(p.returncode == 1 and str(tmp / "empty") in p.stderr and "IMPACTID_FIGURES_DIR" in p.stderr,
               f"no package: exit {p.returncode}, {p.stderr!r}")

        # 4. installed: the package beside the program is the one that runs
        prefix = tmp / "prefix"
        p = run(["cmake", "--install", str(Path(args.build_dir).resolve()), "--component", "program", "--prefix", str(prefix)], tmp)
        installed = prefix / "bin" / "impactid"
        script = prefix / "share" / "impactid" / "figures" / "plot_results.py"
        expect(p.returncode == 0 and installed.exists() and script.exists()
               and (script.parent / "impactid_figures" / "own_results.py").exists(),
               f"cmake --install --component program: exit {p.returncode}\n{p.stdout}{p.stderr}")
        if installed.exists() and script.exists():
            p = run([str(installed), "plot", "grid.h5", "--out", "installed"], tmp)
            expect(p.returncode == 0 and written(p), f"installed plot: exit {p.returncode}\n{p.stdout}{p.stderr}")
            script.write_text("import sys\nprint('the installed package')\nsys.exit(0)\n")
            p = run([str(installed), "plot", "grid.h5"], tmp)
            expect("the installed package" in p.stdout, f"the installed program ran another package: {p.stdout}{p.stderr}")

        # 5. the Python module, installed, finds the package installed with it
        build = Path(args.build_dir).resolve()
        if (build / "python" / "impactid" / "_paths.py").exists():
            pyprefix = tmp / "pyprefix"
            p = run(["cmake", "--install", str(build), "--component", "python", "--prefix", str(pyprefix)], tmp)
            packages = list(pyprefix.glob("lib/python*/dist-packages"))
            expect(p.returncode == 0 and packages, f"cmake --install --component python: {p.stdout}{p.stderr}")
            if packages:
                p = run(["/usr/bin/python3", "-c", "import impactid, sys; print(impactid.plot(sys.argv[1], out='py'))",
                         "grid.h5"], tmp, dict(os.environ, PYTHONPATH=str(packages[0])))
                expect(p.returncode == 0 and "grid-eps_p.png" in p.stdout and (tmp / "py" / "grid-eps_p.png").exists(),
                       f"installed impactid.plot: exit {p.returncode}\n{p.stdout}{p.stderr}")
        else:
            print("note: no Python module in this build: its installed impactid.plot is not checked")

        # 6. the colours are the program's method list's: distinct for every method, and in its order
        figures = Path(__file__).resolve().parent.parent / "figures"
        probe = ("import sys; sys.path.insert(0, sys.argv[1]); from impactid_figures import style; "
                 "print(' '.join(style.registry())); print(' '.join(style.method_color(m) for m in style.registry()))")
        p = run(["/usr/bin/python3", "-c", probe, str(figures)], tmp, dict(os.environ, IMPACTID_EXECUTABLE=impactid))
        names, colors = (p.stdout.splitlines() + ["", ""])[:2]
        methods = [m["name"] for m in json.loads(run([impactid, "methods", "--json"], tmp).stdout)]
        expect(p.returncode == 0 and names.split() == methods, f"style.registry() is not the program's list: {names!r}")
        expect(len(set(colors.split())) == len(names.split()) > 10, f"colours repeat: {names} -> {colors}")
        fake = tmp / "fake-impactid"
        fake.write_text('#!/bin/sh\necho \'[{"name": "kim-explicit"}, {"name": "hht"}]\'\n')
        fake.chmod(0o755)
        p = run(["/usr/bin/python3", "-c", probe, str(figures)], tmp, dict(os.environ, IMPACTID_EXECUTABLE=str(fake)))
        expect(p.stdout.split("\n")[0] == "kim-explicit hht" and p.stdout.split("\n")[1].split()[0] == "#E69F00",
               f"the colours do not follow the program's list: {p.stdout!r} {p.stderr!r}")

    for f in failures:
        print("FAIL", f)
    print(f"plot_command_test: {len(failures)} failures")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
