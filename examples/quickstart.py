#!/usr/bin/python3
"""impactid from Python in three steps (python/README.md): one run against the exact solution,
a small (delta, alpha) grid of HHT as a heat map, and a work-precision plot.

    PYTHONPATH=build/python /usr/bin/python3 examples/quickstart.py [--output DIR]

Writes quickstart-pressure.png, quickstart-grid.png and quickstart-work-precision.png to DIR
(default: a new temporary folder, printed at the end), and the two results files beside them.
"""

import argparse
import pathlib
import tempfile

import matplotlib

matplotlib.use("Agg")  # files only, no display
import matplotlib.pyplot as plt  # noqa: E402

import impactid  # noqa: E402


def pressure_against_exact(out: pathlib.Path) -> None:
    """One run of HHT on the paper's rod (100 elements), its contact pressure over the exact."""
    run = impactid.simulate(method={"name": "hht", "alpha": -0.3, "delta": 0.45}, elements=100)
    print(f"simulate: {run.method} {run.status}, eps_p = {run.eps_p:.4g}, NoP_p = {run.nop_p:g}")
    fig, ax = plt.subplots(figsize=(7, 3.5))
    ax.plot(run.t * 1e6, run.exact_pressure, "k-", lw=1.2, label="exact (d'Alembert)")
    ax.plot(run.t * 1e6, run.pressure, "C0-", lw=0.8, label=f"hht α = −0.3, δ = 0.45")
    ax.set_xlabel("t [µs]")
    ax.set_ylabel(f"contact pressure [{run.units['pressure']}]")
    ax.set_title(f"ε_p = {run.eps_p:.3g}, NoP_p = {run.nop_p:g}")
    ax.legend()
    fig.tight_layout()
    fig.savefig(out / "quickstart-pressure.png", dpi=120)
    plt.close(fig)


def delta_alpha_grid(out: pathlib.Path) -> None:
    """HHT's eps_p over an 11 x 11 (delta, alpha) grid: a plan given as a dict, as tomllib reads
    a plan file."""
    plan = {
        "name": "quickstart-grid",
        "scene": {"elements": 100},
        "method": {"name": "hht"},
        "study": {
            "kind": "grid",
            "axes": {
                "alpha": {"from": -0.5, "to": 0.0, "partitions": 10},
                "delta": {"from": 0.0, "to": 1.0, "partitions": 10},
            },
        },
    }
    ds = impactid.run_plan(plan, output=out / "quickstart-grid.h5")
    ok = ds["status"] == 0
    print(f"run_plan: {ds.attrs['plan_name']}, {int(ok.sum())} of {ok.size} points ok")
    fig, ax = plt.subplots(figsize=(5.5, 4.5))
    ds["eps_p"].where(ok).plot(ax=ax, x="delta", y="alpha", vmin=0, vmax=0.2,
                               cbar_kwargs={"label": "ε_p"})
    ax.plot(-1.5 * ds["alpha"], ds["alpha"], "w--", lw=1, label="δ = −1.5α (eq. 19)")
    ax.legend(loc="lower right")
    ax.set_title("HHT: ε_p (blank: unstable)")
    fig.tight_layout()
    fig.savefig(out / "quickstart-grid.png", dpi=120)
    plt.close(fig)


def work_precision(out: pathlib.Path) -> None:
    """Wall time against eps_p for three methods over three meshes at Courant number 0.5."""
    plan = {
        "name": "quickstart-work-precision",
        "study": {
            "kind": "work-precision",
            "methods": [
                {"method": "newmark", "delta": 0.3},
                {"method": "hht", "alpha": -0.3, "delta": 0.45},
                {"method": "generalized-alpha", "rho_inf": 0.8},
            ],
            "elements": [50, 100, 200],
            "courant": [0.5],
            "repeats": 3,
        },
    }
    ds = impactid.run_plan(plan, output=out / "quickstart-work-precision.h5")
    fig, ax = plt.subplots(figsize=(5.5, 4))
    for i in range(ds.sizes["method"]):
        point = ds.isel(method=i, courant=0)
        ax.loglog(point["wall_time_s"] * 1e3, point["eps_p"], "o-",
                  label=ds.attrs[f"method_label_{i}"])
    ax.set_xlabel("wall time [ms]")
    ax.set_ylabel("ε_p")
    ax.set_title("Work–precision, Courant 0.5, n = 50, 100, 200")
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(out / "quickstart-work-precision.png", dpi=120)
    plt.close(fig)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--output", type=pathlib.Path, help="folder for the PNGs (default: temporary)")
    out = parser.parse_args().output or pathlib.Path(tempfile.mkdtemp(prefix="impactid-quickstart-"))
    out.mkdir(parents=True, exist_ok=True)
    pressure_against_exact(out)
    delta_alpha_grid(out)
    work_precision(out)
    print(f"wrote {out}/quickstart-pressure.png, quickstart-grid.png, quickstart-work-precision.png")


if __name__ == "__main__":
    main()
