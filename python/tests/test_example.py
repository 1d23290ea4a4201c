"""examples/quickstart.py runs and writes its three figures."""

import os
import subprocess
import sys


def test_quickstart_writes_its_figures(source_dir, tmp_path, child_env):
    done = subprocess.run([sys.executable, str(source_dir / "examples" / "quickstart.py"),
                           "--output", str(tmp_path)], capture_output=True, text=True, env=child_env,
                          cwd=tmp_path)
    assert done.returncode == 0, done.stderr
    for name in ("quickstart-pressure.png", "quickstart-grid.png",
                 "quickstart-work-precision.png"):
        png = tmp_path / name
        assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n", name
        assert png.stat().st_size > 10_000, name  # a plot, not an empty canvas
