"""impactid.kernels(): which batched kernels run, as `impactid --version` says; a level the
processor lacks, forced with IMPACTID_KERNELS, is refused at import (core/common/kernel_level.hpp)."""

import subprocess
import sys

import impactid


def test_kernels_name_what_runs_and_what_is_supported(executable):
    text = impactid.kernels()
    assert "processor supports" in text
    version = subprocess.run([executable, "--version"], capture_output=True, text=True,
                             check=True).stdout
    assert f"kernels {text}" in version


def test_a_forced_level_runs_and_an_unknown_one_is_refused_at_import(child_env):
    env = dict(child_env, IMPACTID_KERNELS="baseline")
    forced = subprocess.run([sys.executable, "-c", "import impactid; print(impactid.kernels())"],
                            env=env, capture_output=True, text=True)
    assert forced.returncode == 0, forced.stderr
    assert forced.stdout.startswith("baseline (")
    assert "forced by IMPACTID_KERNELS" in forced.stdout

    env = dict(child_env, IMPACTID_KERNELS="avx2")
    refused = subprocess.run([sys.executable, "-c", "import impactid"], env=env,
                             capture_output=True, text=True)
    assert refused.returncode != 0
    assert "IMPACTID_KERNELS = 'avx2': must be baseline, x86-64-v3 or x86-64-v4" in refused.stderr
