#!/usr/bin/python3
"""docs/model-files.md cannot drift from the program:

1. every block marked `<!-- model-files-doc: PATH -->` is the file PATH as it is (a Matrix
   Market file's `%` comment lines aside);
2. the page's shell block runs as written, from the project root, with its /tmp/ outputs in a
   temporary folder: the example model simulates, its plan runs, its results plot;
3. each error the page quotes is what the program says for that mistake: the example is broken
   one way at a time, `impactid simulate --scene` must exit 2 with the quoted words, and the page
   must quote them.

    tests/model_files_doc_test.py --impactid build/study/impactid --source-dir .
"""

import argparse
import os
import re
import shutil
import subprocess
import sys
import tempfile
from pathlib import Path

DOC = "docs/model-files.md"
EXAMPLE = "examples/three-dof"
MARKER = re.compile(r"^<!--\s*model-files-doc:\s*(?P<path>\S+)\s*-->\s*$")


def replace(old, new):
    def edit(text):
        if old not in text:
            raise AssertionError(f"the example's scene.toml has no {old!r} to break")
        return text.replace(old, new, 1)
    return edit


def append(extra):
    return lambda text: text + extra


def before_matrices(extra):
    return replace("[scene.matrices]", extra + "\n[scene.matrices]")


# (what, edit of scene.toml, {file: content} to write beside it, the words the page and the program share)
MISTAKES = [
    ("no kind", replace('kind = "matrices"', 'kind = "model"'), {},
     'is not a kind of scene: "matrices" (a user\'s model) is the one kind given by name'),
    ("no dt", replace("dt = 5e-4 ", "# "), {}, "a model needs its time step dt (or courant)"),
    ("bad dt", replace("dt = 5e-4", "dt = -5e-4"), {}, "must be positive and finite"),
    ("dt and courant", before_matrices("courant = 0.5"), {}, "cannot be given with dt"),
    ("no t_end", replace("t_end = 0.08", "# t_end"), {}, "a model needs its end time t_end"),
    ("short t_end", replace("t_end = 0.08", "t_end = 1e-5"), {}, "must be finite and at least dt"),
    ("tiny dt", replace("dt = 5e-4", "dt = 1e-12"), {}, "gives more than 1e8 time steps"),
    ("primary", before_matrices('primary_contact = "floor"'), {}, "is not a contact of the model"),
    ("rayleigh", before_matrices("rayleigh_mass = -1.0"), {}, "must be non-negative and finite"),
    ("rod key", before_matrices("length = 3.0"), {},
     'is a key of the one-body rod: a model (kind = "matrices") has its matrices, initial state and contacts instead'),
    ("rod mass", before_matrices('mass = "consistent"'), {},
     "is a key of the one-body rod: a model's mass matrix is its file ([scene.matrices] mass; lump it there)"),
    ("units", replace('units = "N, m, s, kg"', "units = 3"), {}, "must be a string"),
    ("no mass", replace('mass = "M.mtx"', ""), {}, "is missing: the mass matrix file"),
    ("matrices key", replace('stiffness = "K.mtx"', 'stiffness = "K.mtx"\ndampng = "K.mtx"'), {},
     "unknown key (mass, stiffness, damping)"),
    ("device", replace('"K.mtx"', '"/dev/null"'), {}, "is not a regular file"),
    ("not square", replace('"M.mtx"', '"bad.mtx"'),
     {"bad.mtx": "%%MatrixMarket matrix coordinate real general\n3 2 1\n1 1 2.0\n"},
     "is not square: 3 rows, 2 columns"),
    ("size", replace('"K.mtx"', '"bad.mtx"'),
     {"bad.mtx": "%%MatrixMarket matrix coordinate real symmetric\n2 2 1\n1 1 1.0\n"},
     "has 2 rows, where the mass matrix has 3"),
    ("not symmetric", replace('"K.mtx"', '"bad.mtx"'),
     {"bad.mtx": "%%MatrixMarket matrix coordinate real general\n3 3 2\n1 2 1.0\n2 1 3.0\n"},
     "is not symmetric: entry (2, 1) is 3 and (1, 2) is 1 (1-based, as in the file)"),
    ("not definite", replace('"M.mtx"', '"bad.mtx"'),
     {"bad.mtx": "%%MatrixMarket matrix coordinate real symmetric\n3 3 3\n1 1 2.0\n2 2 -1.0\n3 3 2.0\n"},
     "is not positive definite: pivot -1 at DOF 1 (row 2 of the file)"),
    ("slice", append('[scene.dof_sets]\nodd = "1:x"\n'), {}, '"1:x" is not a slice start:stop:step'),
    ("slice step", append('[scene.dof_sets]\nodd = "1::-1"\n'), {}, "the step must be positive"),
    ("empty slice", append('[scene.dof_sets]\nnone = "2:1"\n'), {}, "selects no DOF of the 3"),
    ("dof range", replace("dof = 2 ", "dof = 3 "), {}, "DOF 3 is out of range: the model has 3 DOFs, 0 to 2"),
    ("initial size", replace('velocity = { value = 1.0, dofs = "all" }', 'velocity = "v0.mtx"'),
     {"v0.mtx": "%%MatrixMarket matrix array real general\n2 1\n1.0\n1.0\n"},
     "has 2 entries, where the model has 3 DOFs"),
    ("initial set", replace('dofs = "all"', 'dofs = "odd"'), {},
     '"odd" is not a set of DOFs: give a list, "all", a slice "start:stop:step", or the name of a [scene.dof_sets] entry'),
    ("initial key", replace("velocity = {", "velocty = {"), {}, "unknown key (displacement, velocity)"),
    ("load force", append('[scene.load]\npotential_at_rest = 1.0\n'), {}, "is missing: the constant force on every DOF"),
    ("load key", append('[scene.load]\nforce = { value = 1.0 }\nforse = 1.0\n'), {},
     "unknown key (force, potential_at_rest)"),
    ("no contact", lambda t: t[:t.index("[[scene.contact]]")], {}, "a model needs at least one [[scene.contact]] table"),
    ("contact name", replace('name = "wall"', 'name = "the wall"'), {}, "must be letters, digits, '_' or '-'"),
    ("two names", append('[[scene.contact]]\nname = "wall"\ndof = 0\nside = "lower"\n'), {}, "names two contacts"),
    ("two walls", append('[[scene.contact]]\nname = "floor"\ndof = 2\nside = "lower"\n'), {}, "already has a wall"),
    ("side", replace("dof = 2 ", 'side = "up"\ndof = 2 '), {},
     'is not a side: "upper" (u <= gap) or "lower" (u >= -gap)'),
    ("pair side", append('[[scene.contact]]\nname = "pair"\ndofs = [0, 1]\nside = "upper"\n'), {},
     "applies to a wall (dof), not a pair"),
    ("pair", append('[[scene.contact]]\nname = "pair"\ndofs = [0]\n'), {},
     "must be a pair of DOFs [i, j]: u_i − u_j <= gap"),
    ("pair twice", append('[[scene.contact]]\nname = "pair"\ndofs = [1, 1]\n'), {}, "must be two different DOFs"),
    ("dof and dofs", replace("dof = 2 ", "dofs = [1, 2]\ndof = 2 "), {}, "cannot be given with dof"),
    ("gap", replace("gap = 0.01", "gap = -0.01"), {}, "a gap must be >= 0"),
    ("area", replace("area = 1e-4", "area = 0.0"), {}, "an area must be > 0"),
    ("repeat", append('[[scene.contact]]\nname = "again"\ndof = 2\n'), {}, 'repeats the constraint of contact "wall"'),
    ("reference format", append('[scene.reference]\nfile = "r.txt"\n'), {"r.txt": "t\n"},
     "unknown format (a reference history is a .csv, .h5 or .hdf5 file)"),
    ("reference value", append('[scene.reference]\nfile = "r.csv"\n'),
     {"r.csv": "t,wall.pressure,wall.velocity\n0.001,0,1\n0.002,x,1\n"}, 'r.csv:3: "x" is not a finite number'),
    ("reference time", append('[scene.reference]\nfile = "r.csv"\n'),
     {"r.csv": "t,wall.pressure\n0.002,0\n0.001,0\n"}, "t must increase"),
    ("reference column", append('[scene.reference]\nfile = "r.csv"\n'),
     {"r.csv": "t,w.force\n0.001,0\n"},
     'column "w.force" is not <contact>.pressure or <contact>.velocity of a contact of the model'),
    ("reference not one", append('[scene.reference]\nfile = "r.csv"\n'),
     {"r.csv": "root:secret-token:0:0\n"},
     "is not a reference history: its header's first column must be t"),
]


def flat(text):
    """Markdown text as one line: wrapped lines joined, code spans and table bars gone."""
    return re.sub(r"\s+", " ", text.replace("`", "").replace("\\|", "|"))


def marked_blocks(doc):
    lines = doc.split("\n")
    out = []
    for i, line in enumerate(lines):
        m = MARKER.match(line.strip())
        if not m:
            continue
        if i + 1 >= len(lines) or not lines[i + 1].startswith("```"):
            raise AssertionError(f"{DOC}:{i + 1}: a marker must sit on the line before a fence")
        end = lines.index("```", i + 2)
        out.append((i + 1, m.group("path"), "\n".join(lines[i + 2:end]) + "\n"))
    return out


def without_comments(text):
    return "".join(line + "\n" for line in text.split("\n")
                   if line and (not line.startswith("%") or line.startswith("%%")))


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--impactid", required=True)
    parser.add_argument("--source-dir", required=True)
    args = parser.parse_args()
    root = Path(args.source_dir).resolve()
    impactid = str(Path(args.impactid).resolve())
    doc = (root / DOC).read_text(encoding="utf-8")
    failures = []

    blocks = marked_blocks(doc)
    if len(blocks) < 4:
        failures.append(f"{DOC}: {len(blocks)} marked blocks, expected M.mtx, K.mtx, scene.toml and the plan")
    for line, path, text in blocks:
        actual = (root / path).read_text(encoding="utf-8")
        if path.endswith(".mtx"):
            actual, text = without_comments(actual), without_comments(text)
        if actual != text:
            failures.append(f"{DOC}:{line}: the block differs from {path}")

    with tempfile.TemporaryDirectory(prefix="model-files-doc-") as tmp:
        env = dict(os.environ, PATH=str(Path(impactid).parent) + os.pathsep + os.environ["PATH"])
        shell = re.search(r"Run it from the project root.*?```sh\n(.*?)```", doc, re.S)
        if not shell:
            failures.append(f"{DOC}: no shell block after 'Run it from the project root'")
        else:
            for command in filter(None, (c.strip() for c in shell.group(1).split("\n"))):
                command = command.replace("/tmp/", tmp + "/")
                run = subprocess.run(["bash", "-c", command], cwd=root, env=env, capture_output=True, text=True,
                                     timeout=300)
                if run.returncode != 0:
                    failures.append(f"{command}: exit {run.returncode}\n{run.stdout}{run.stderr}")
            figures = list(Path(tmp).glob("three-dof-methods-figures/*.png"))
            if not figures or any(f.stat().st_size == 0 for f in figures):
                failures.append(f"impactid plot wrote no figure of the example's results: {figures}")

        # The misplaced scene file, quoted whole on the page.
        plan_dir = Path(tmp) / "misplaced"
        shutil.copytree(root / EXAMPLE, plan_dir)
        (plan_dir / "plan.toml").write_text('name = "misplaced"\n[scene]\nscene = "scene.toml"\n[method]\n'
                                            'name = "hht"\n[study]\nkind = "grid"\n[study.axes]\n'
                                            'alpha = { values = [-0.1] }\n')
        run = subprocess.run([impactid, "run", "plan.toml", "--dry-run"], cwd=plan_dir, capture_output=True, text=True)
        quoted = re.search(r"^plan\.toml:3:9: scene\.scene = .*$", doc, re.M)
        if run.returncode != 2 or not quoted or quoted.group(0) not in run.stderr:
            failures.append(f"misplaced scene: exit {run.returncode}, stderr {run.stderr!r}; the page quotes "
                            f"{quoted.group(0) if quoted else None!r}")

        page = flat(doc)
        for what, edit, files, words in MISTAKES:
            case = Path(tmp) / re.sub(r"\W", "_", what)
            shutil.copytree(root / EXAMPLE, case)
            scene = case / "scene.toml"
            scene.write_text(edit(scene.read_text()))
            for name, content in files.items():
                (case / name).write_text(content)
            run = subprocess.run([impactid, "simulate", "--scene", "scene.toml"], cwd=case, capture_output=True,
                                 text=True, timeout=60)
            if run.returncode != 2 or words not in run.stderr:
                failures.append(f"{what}: exit {run.returncode}, expected 2 with {words!r}; stderr: {run.stderr.strip()}")
            elif "secret-token" in run.stderr:  # a file that is not what it should be is not echoed
                failures.append(f"{what}: the message shows the file's content: {run.stderr.strip()}")
            elif "scene.toml:" not in run.stderr and "r.csv" not in words:
                failures.append(f"{what}: the message does not name the file: {run.stderr.strip()}")
            if flat(words) not in page:
                failures.append(f"{what}: {DOC} does not quote {words!r}")

    for f in failures:
        print("FAIL", f)
    print(f"{DOC}: {len(blocks)} blocks, {len(MISTAKES)} errors checked, {len(failures)} failures")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
