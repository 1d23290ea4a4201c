"""A results file that cannot be written raises OSError naming the file and the reason, and the
interpreter lives on (issue 38: HDF5 crashed in H5Fclose and took Python with it)."""

import subprocess
import sys

SCRIPT = """
import resource, sys
import impactid
resource.setrlimit(resource.RLIMIT_FSIZE, (16 * 1024, resource.RLIM_INFINITY))
try:
    impactid.run_plan(sys.argv[1], output=sys.argv[2])
except OSError as e:
    print("OSError:", e)
print("alive")
"""


def test_a_write_past_the_file_size_limit_raises_and_the_interpreter_lives(child_env, tmp_path,
                                                                           source_dir):
    target = tmp_path / "demo.h5"
    result = subprocess.run([sys.executable, "-c", SCRIPT, str(source_dir / "plans" / "demo.toml"),
                             str(target)], env=child_env, capture_output=True, text=True)
    assert result.returncode == 0, result.stderr
    assert f"OSError: {target}: cannot write {target}.tmp: File too large" in result.stdout
    assert result.stdout.rstrip().endswith("alive")
    assert not target.exists() and not (tmp_path / "demo.h5.tmp").exists()
