#!/usr/bin/python3
"""End-to-end check of the figure generator, for ctest:

    check_figures.py [--impactid PATH] [--keep DIR]

1. writes small versions of the figure plans (a 40-element rod, a few grid points; the
   work-precision study on 20 and 40 elements, timed once; the scenes of bodies of
   plans/hopkinson.toml, two-rods.toml and stepped-rod.toml on 40 to 80 elements; the plans of the
   shipped block model, examples/block/, on a few points, with a loose reference tolerance) to a
   temporary folder and runs `impactid run` on each, from that folder, so the results and the
   per-point histories land in TMP/results/;
2. runs plans/spectral.toml of the project too, if it exists (its results go to
   TMP/results/spectral.h5 through --output);
3. runs figures/make_figures.py on TMP/results and checks that it exits with 0, prints one
   `wrote` line per expected figure, and that every PNG exists, is a PNG and is larger than a
   few kB (an empty set of axes is about 5 kB at 150 dpi; a drawn figure is far larger);
4. runs make_figures.py on an empty folder and checks that it skips every figure, naming the
   missing file and the command that produces it, with exit status 0;
5. runs `impactid plot` on every results file of step 1 (every study kind the shipped plans
   have: grids of one, two and three axes, a choice axis, lists, optimisations, work-precision,
   spectral, scenes of bodies, the block model) and on one time-history file of each history
   folder, and checks that it exits with 0 and that every PNG it names is a PNG of a real figure.

Exit status 0 if all holds, 1 otherwise (the failed checks are printed). Takes a few seconds.
"""

import argparse
import os
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

PROJECT_ROOT = Path(__file__).resolve().parent.parent
MAKE_FIGURES = PROJECT_ROOT / "figures" / "make_figures.py"
PYTHON = "/usr/bin/python3"
MIN_BYTES = 20_000  # every real figure here is 60 kB or more; a blank 12x5 in canvas is ~5 kB

SCENE = """
[scene]
elements = 40
"""

# The thresholds of the figure plans: the results then carry the `practical` column and the
# practical_* attributes that the figures shade and outline.
PRACTICAL = """
[study.practical]
eps_p = 0.03
nop_p = 15
"""

# Small stand-ins for the plans of plans/ (same names, so the same figures), on a 40-element rod.
PLANS = {
    "newmark-delta": f"""
name = "newmark-delta"
description = "check_figures: Newmark over delta, 40 elements"
{SCENE}
[method]
name = "newmark"

[study]
kind = "grid"

[study.axes]
delta = {{ from = 0.0, to = 1.0, partitions = 10 }}
{PRACTICAL}""",
    "hht-delta-alpha": f"""
name = "hht-delta-alpha"
description = "check_figures: HHT over delta x alpha, 40 elements"
{SCENE}
[method]
name = "hht"

[study]
kind = "grid"

[study.axes]
alpha = {{ from = -0.5, to = 0.0, partitions = 5 }}
delta = {{ from = 0.0, to = 1.0, partitions = 10 }}
{PRACTICAL}""",
    "hht-period-error-line": f"""
name = "hht-period-error-line"
description = "check_figures: HHT along delta = -1.5 alpha, 40 elements"
{SCENE}
[method]
name = "hht"

[study]
kind = "grid"

[study.axes]
alpha = {{ from = -0.5, to = 0.0, partitions = 10 }}
delta = "-1.5*alpha"
{PRACTICAL}""",
    "hht-optimize": f"""
name = "hht-optimize"
description = "check_figures: HHT, minimise eps_p subject to NoP_p <= 15, 40 elements"
{SCENE}
[method]
name = "hht"

[study]
kind = "optimize"
algorithm = "COBYLA"
objective = "eps_p"
max_evaluations = 20

[study.parameters]
delta = {{ from = 0.0, to = 1.0, start = 0.75 }}
alpha = {{ from = -0.5, to = 0.0, start = -0.5 }}

[study.constraints]
nop_p = {{ max = 15 }}
""",
    # The parameters are placeholders, not matched dissipation: the check tests the drawing.
    "identical-dissipation": f"""
name = "identical-dissipation"
description = "check_figures: the five methods, 40 elements, with histories"
{SCENE}
[study]
kind = "list"
points = [
  {{ method = "cdm" }},
  {{ method = "backward-euler" }},
  {{ method = "newmark", delta = 0.2 }},
  {{ method = "hht", alpha = -0.3, delta = 0.45 }},
  {{ method = "generalized-alpha", rho_inf = 0.6 }},
]
{PRACTICAL}
[output]
histories = "results/histories/identical-dissipation"
""",
    # Scenes of bodies ([[scene.body]]), small stand-ins for plans/hopkinson.toml, two-rods.toml
    # and stepped-rod.toml: the maps, the δ sweep and the histories at a contact of a chain.
    "hopkinson": f"""
name = "hopkinson"
description = "check_figures: striker on a bar, HHT over delta x alpha, 20 + 60 elements"

[scene]
[[scene.body]]
name = "striker"
velocity = 1000.0
length = 10.0
elements = 20

[[scene.body]]
name = "bar"
gap = 0.01
length = 30.0
elements = 60

[method]
name = "hht"

[study]
kind = "grid"

[study.axes]
alpha = {{ from = -0.5, to = 0.0, partitions = 5 }}
delta = {{ from = 0.0, to = 1.0, partitions = 10 }}
{PRACTICAL}""",
    # plans/clamped-bar.toml on 20 elements: a clamped end and an initial displacement field.
    "clamped-bar": f"""
name = "clamped-bar"
description = "check_figures: clamped bar on an obstacle, HHT over delta x alpha, 20 elements"

[scene]
courant = 1.0
t_end = 6.0
[[scene.body]]
name = "bar"
length = 1.0
elements = 20
youngs_modulus = 1.0
density = 1.0
area = 1.0
displacement = [0.5, 0.0]

[scene.wall.left]
gap = 0.0

[scene.wall.right]
kind = "clamped"

[method]
name = "hht"

[study]
kind = "grid"

[study.axes]
alpha = {{ from = -0.5, to = 0.0, partitions = 5 }}
delta = {{ from = 0.0, to = 1.0, partitions = 10 }}
{PRACTICAL}""",
    # plans/bouncing-bar.toml on 20 elements over one period: gravity.
    "bouncing-bar": f"""
name = "bouncing-bar"
description = "check_figures: bouncing bar under gravity, HHT over delta x alpha, 20 elements"

[scene]
courant = 1.0
t_end = 5.333333333333333
gravity = -10.0
[[scene.body]]
name = "bar"
length = 10.0
elements = 20
youngs_modulus = 900.0
density = 1.0
area = 1.0

[scene.wall.left]
gap = 5.0

[method]
name = "hht"

[study]
kind = "grid"

[study.axes]
alpha = {{ from = -0.5, to = 0.0, partitions = 5 }}
delta = {{ from = 0.0, to = 1.0, partitions = 10 }}
{PRACTICAL}""",
    "two-rods": f"""
name = "two-rods"
description = "check_figures: two equal rods, Newmark over delta, 40 + 40 elements"

[scene]
[[scene.body]]
name = "striker"
velocity = 1000.0
length = 20.0
elements = 40

[[scene.body]]
name = "target"
gap = 0.01
length = 20.0
elements = 40

[method]
name = "newmark"

[study]
kind = "grid"

[study.axes]
delta = {{ from = 0.0, to = 1.0, partitions = 10 }}
{PRACTICAL}""",
    "stepped-rod": f"""
name = "stepped-rod"
description = "check_figures: a stepped rod (A : 4A) on a wall, the five methods, 20 + 20 elements, with histories"

[scene]
[[scene.body]]
name = "rod"
velocity = 1000.0
[[scene.body.segment]]
length = 10.0
elements = 20
area = 4.0
[[scene.body.segment]]
length = 10.0
elements = 20
area = 1.0

[scene.wall.right]
gap = 0.01

[study]
kind = "list"
points = [
  {{ method = "cdm" }},
  {{ method = "backward-euler" }},
  {{ method = "newmark", delta = 0.2 }},
  {{ method = "hht", alpha = -0.3, delta = 0.45 }},
  {{ method = "generalized-alpha", rho_inf = 0.6 }},
]
{PRACTICAL}
[output]
histories = "results/histories/stepped-rod"
""",
    "stability-map": f"""
name = "stability-map"
description = "check_figures: HHT status over Courant x alpha x delta, 40 elements"
{SCENE}
[method]
name = "hht"

[study]
kind = "grid"

[study.axes]
courant = {{ values = [0.5, 20.0] }}
alpha = {{ from = -0.5, to = 0.0, partitions = 4 }}
delta = {{ from = 0.0, to = 1.0, partitions = 4 }}

[output]
indicators = ["energy_ratio"]
""",
    # Central difference at Courant 2 is unstable: the figure's strip of not-ok runs is drawn too.
    "work-precision": """
name = "work-precision"
description = "check_figures: two methods over two meshes and two Courant numbers, timed once"

[study]
kind = "work-precision"
methods = [
  { method = "cdm" },
  { method = "hht", alpha = -0.3, delta = 0.45 },
]
elements = [20, 40]
courant = [0.5, 2.0]
repeats = 1
""",
    # The two-parameter maps of rho-Bathe and Noh-Bathe explicit (points past its limit: not ok).
    "rho-bathe": """
name = "rho-bathe"
""" + SCENE + """
[method]
name = "rho-bathe"
[study]
kind = "grid"
[study.axes]
rho_inf = { from = 0.0, to = 0.4, partitions = 2 }
substep_ratio = { from = 0.7, to = 0.9, partitions = 2 }
[study.practical]
eps_p = 0.03
""",
    "noh-bathe": """
name = "noh-bathe"
""" + SCENE + """
[method]
name = "noh-bathe"
[study]
kind = "grid"
[study.axes]
p = { values = [0.5, 0.54, 0.7] }
courant = { values = [0.5, 1.9] }
""",
    "kim-explicit": """
name = "kim-explicit"
""" + SCENE + """
[method]
name = "kim-explicit"
[study]
kind = "grid"
[study.axes]
p = { values = [0.3333333333333333, 0.45] }
courant = { values = [0.5, 1.5] }
""",
    # KR-alpha explicit over rho_inf and the Courant number (unconditionally stable).
    "kr-alpha": """
name = "kr-alpha"
""" + SCENE + """
[method]
name = "kr-alpha"
[study]
kind = "grid"
[study.axes]
rho_inf = { values = [0.0, 0.5, 1.0] }
courant = { values = [0.5, 2.0] }
""",
    # The contact laws as a choice axis crossed with the penalty stiffness.
    "contact-laws": """
name = "contact-laws"
""" + SCENE + """
[method]
name = "hht"
[study]
kind = "grid"
[study.axes]
contact = { values = ["lagrange", "penalty", "augmented-lagrangian"] }
penalty_factor = { values = [0.1, 1.0, 10.0] }
""",
}

# The shipped block model (examples/block: 1722 DOFs, 41 contacts), read from the project: small
# stand-ins for examples/block/*.toml (same names, so the same figures). Its indicators are measured
# against a converged reference; the work-precision study's looser tolerance (the check tests the
# drawing) keeps its references at a few halvings: 0.1 s (at the default 0.001 and Courant 0.5, 20 s).
BLOCK_SCENE = f"scene = '{PROJECT_ROOT / 'examples' / 'block' / 'scene.toml'}'"
PLANS.update({
    "block-hht-delta-alpha": f"""
name = "block-hht-delta-alpha"
description = "check_figures: HHT over delta x alpha on the block model"
{BLOCK_SCENE}

[method]
name = "hht"

[study]
kind = "grid"

[study.axes]
alpha = {{ from = -0.5, to = 0.0, partitions = 2 }}
delta = {{ from = 0.0, to = 1.0, partitions = 4 }}
{PRACTICAL}""",
    # The parameters are placeholders, not matched dissipation: the check tests the drawing.
    "block-identical-dissipation": f"""
name = "block-identical-dissipation"
description = "check_figures: the five methods on the block model, with histories"
{BLOCK_SCENE}

[study]
kind = "list"
points = [
  {{ method = "hht", alpha = -0.3, delta = 0.45 }},
  {{ method = "newmark", delta = 0.2 }},
  {{ method = "generalized-alpha", rho_inf = 0.6 }},
  {{ method = "backward-euler" }},
  {{ method = "cdm" }},
]

[output]
histories = "results/histories/block-identical-dissipation"
""",
    # Central difference at Courant 2 (of the model's bound of omega_max) is unstable: the strip.
    "block-work-precision": f"""
name = "block-work-precision"
description = "check_figures: two methods on the block model at two Courant numbers, timed once"
{BLOCK_SCENE}

[study]
kind = "work-precision"
methods = [
  {{ method = "cdm" }},
  {{ method = "hht", alpha = -0.3, delta = 0.45 }},
]
courant = [0.6, 2.0]
repeats = 1

[output]
reference_tolerance = 0.5
""",
})

# A work-precision study times its runs one at a time on one thread and refuses --threads.
SINGLE_THREAD = {"work-precision", "block-work-precision"}

FIGURES = {
    "fig3_newmark_delta.png": ["newmark-delta"],
    "fig4_hht_delta_alpha.png": ["hht-delta-alpha"],
    "fig_hopkinson.png": ["hopkinson"],
    "fig_clamped_bar.png": ["clamped-bar"],
    "fig_bouncing_bar.png": ["bouncing-bar"],
    "fig_two_rods.png": ["two-rods"],
    "fig_period_error_line.png": ["hht-period-error-line"],
    "fig5_pressure_history.png": ["identical-dissipation"],
    "fig6_velocity_history.png": ["identical-dissipation"],
    "fig_stepped_rod_pressure.png": ["stepped-rod"],
    "fig_stepped_rod_velocity.png": ["stepped-rod"],
    "fig7_compare_pressure.png": ["identical-dissipation"],
    "fig8_compare_velocity.png": ["identical-dissipation"],
    "fig_spectral.png": ["spectral"],
    "fig_optimize.png": ["hht-optimize", "hht-delta-alpha"],
    "fig_stability_map.png": ["stability-map"],
    "fig_work_precision.png": ["work-precision"],
    "block-hht-delta-alpha.png": ["block-hht-delta-alpha"],
    "block-contact-force.png": ["block-identical-dissipation"],
    "block-work-precision.png": ["block-work-precision"],
    "fig_contact_laws.png": ["contact-laws"],
    "fig_paoli_schatzman.png": ["paoli-schatzman"],
    "fig_rho_bathe.png": ["rho-bathe"],
    "fig_noh_bathe.png": ["noh-bathe"],
    "fig_kim_explicit.png": ["kim-explicit"],
    "fig_kr_alpha.png": ["kr-alpha"],
}


def run(cmd, cwd, what, env=None):
    start = time.monotonic()
    p = subprocess.run(cmd, cwd=cwd, capture_output=True, text=True, timeout=120, env=env)
    took = time.monotonic() - start
    return p, took


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--impactid", default=str(PROJECT_ROOT / "build" / "study" / "impactid"),
                        help="the impactid program (default: build/study/impactid)")
    parser.add_argument("--keep", default=None, help="work in this folder and keep it (default: a temporary one)")
    args = parser.parse_args()
    impactid = Path(args.impactid).resolve()
    if not impactid.exists():
        print(f"check_figures: --impactid {impactid}: not found (build it first)")
        return 1

    failures = []
    tmp = Path(args.keep) if args.keep else Path(tempfile.mkdtemp(prefix="impactid-figures-"))
    tmp.mkdir(parents=True, exist_ok=True)
    try:
        (tmp / "plans").mkdir(exist_ok=True)
        (tmp / "results").mkdir(exist_ok=True)
        made = set()
        for name, plan in PLANS.items():
            path = tmp / "plans" / f"{name}.toml"
            path.write_text(plan.lstrip())
            threads = [] if name in SINGLE_THREAD else ["--threads", "2"]
            p, took = run([str(impactid), "run", str(path), *threads, "--output",
                           str(tmp / "results" / f"{name}.h5")], tmp, name)
            if p.returncode != 0:
                failures.append(f"impactid run {name}: exit {p.returncode}\n{p.stdout}{p.stderr}")
            else:
                made.add(name)
                print(f"ran {name} in {took:.1f} s")
        spectral_plan = PROJECT_ROOT / "plans" / "spectral.toml"
        if spectral_plan.exists():
            shutil.copy(spectral_plan, tmp / "plans" / "spectral.toml")
            p, took = run([str(impactid), "run", str(tmp / "plans" / "spectral.toml"), "--output",
                           str(tmp / "results" / "spectral.h5")], tmp, "spectral")
            if p.returncode != 0:
                failures.append(f"impactid run plans/spectral.toml: exit {p.returncode}\n{p.stdout}{p.stderr}")
            else:
                made.add("spectral")
                print(f"ran spectral in {took:.1f} s")
        else:
            print("note: no plans/spectral.toml yet: fig_spectral.png is expected to be skipped")

        # 3. every figure whose inputs exist is drawn
        out = tmp / "figures"
        # the figures' colours come from this program's method list (figures/impactid_figures/style.py)
        env = dict(os.environ, IMPACTID_EXECUTABLE=str(impactid))
        p, took = run([PYTHON, str(MAKE_FIGURES), "--results", str(tmp / "results"), "--out", str(out)], tmp, "figures",
                      env)
        print(p.stdout, end="")
        print(f"make_figures.py took {took:.1f} s")
        if p.returncode != 0:
            failures.append(f"make_figures.py: exit {p.returncode}\n{p.stderr}")
        for fig, needs in FIGURES.items():
            expected = all(n in made for n in needs)
            png = out / fig
            if expected:
                if f"wrote   {png}" not in p.stdout:
                    failures.append(f"{fig}: no 'wrote' line")
                if not png.exists():
                    failures.append(f"{fig}: not written")
                    continue
                data = png.read_bytes()
                if not data.startswith(b"\x89PNG\r\n\x1a\n"):
                    failures.append(f"{fig}: not a PNG file")
                if len(data) < MIN_BYTES:
                    failures.append(f"{fig}: only {len(data)} bytes (< {MIN_BYTES}): an empty figure?")
            elif f"skipped {fig}:" not in p.stdout:
                failures.append(f"{fig}: its input is missing but it was not reported as skipped")

        # 4. with no results at all, every figure is skipped with the command that makes its data
        empty = tmp / "empty"
        empty.mkdir(exist_ok=True)
        p, _ = run([PYTHON, str(MAKE_FIGURES), "--results", str(empty), "--out", str(tmp / "empty-figures")], tmp, "empty")
        if p.returncode != 0:
            failures.append(f"make_figures.py on an empty folder: exit {p.returncode}\n{p.stderr}")
        lines = p.stdout.splitlines()
        for fig in FIGURES:
            line = next((l for l in lines if l.startswith(f"skipped {fig}:")), None)
            if line is None:
                failures.append(f"empty folder: {fig} not reported as skipped:\n{p.stdout}")
            elif not any(f"impactid run {d}/" in line for d in ("plans", "examples/block")) or "not found" not in line:
                failures.append(f"empty folder: the skip message does not name the file and the command: {line}")
        if list((tmp / "empty-figures").glob("*.png")):
            failures.append("empty folder: PNG files were written anyway")

        # 5. impactid plot draws every results file and a history file of each folder
        inputs = sorted((tmp / "results").glob("*.h5"))
        inputs += [sorted(d.glob("point-*.h5"))[0] for d in sorted((tmp / "results" / "histories").glob("*"))
                   if list(d.glob("point-*.h5"))]
        for path in inputs:
            folder = tmp / "plot" / (path.stem if path.parent.name == "results" else f"{path.parent.name}-{path.stem}")
            p, took = run([str(impactid), "plot", str(path), "--out", str(folder)], tmp, "plot")
            pngs = [Path(line[len("wrote "):]) for line in p.stdout.splitlines() if line.startswith("wrote ")]
            if p.returncode != 0 or not pngs:
                failures.append(f"impactid plot {path.relative_to(tmp)}: exit {p.returncode}, {len(pngs)} files\n"
                                f"{p.stdout}{p.stderr}")
            for png in pngs:
                data = png.read_bytes() if png.exists() else b""
                if not data.startswith(b"\x89PNG\r\n\x1a\n") or len(data) < MIN_BYTES:
                    failures.append(f"impactid plot {path.name}: {png} is not a PNG of {MIN_BYTES} bytes or more "
                                    f"({len(data)})")
            print(f"plotted {path.relative_to(tmp)}: {len(pngs)} figures in {took:.1f} s")
    finally:
        if not args.keep:
            shutil.rmtree(tmp, ignore_errors=True)

    if failures:
        print("\nFAILED:\n" + "\n".join(f"- {f}" for f in failures))
        return 1
    print("check_figures: all figures OK")
    return 0


if __name__ == "__main__":
    sys.exit(main())
