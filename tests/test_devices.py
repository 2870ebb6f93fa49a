"""`import impedax` gives JAX one CPU device per core (batch fits run a chunk on each), unless
the user chose otherwise or JAX already runs."""

import os
import subprocess
import sys

import pytest

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def devices_after(code: str, **env) -> int:
    environment = {k: v for k, v in os.environ.items() if k not in ("IMPEDAX_CPU_DEVICES", "XLA_FLAGS")}
    environment.update(env, PYTHONPATH=ROOT)
    out = subprocess.run([sys.executable, "-c", code + "\nimport jax; print(len(jax.devices()))"], env=environment, capture_output=True, text=True, timeout=120)
    assert out.returncode == 0, out.stderr
    return int(out.stdout.split()[-1])


def test_one_device_per_core_by_default():
    assert devices_after("import impedax") == min(len(os.sched_getaffinity(0)), 8)


@pytest.mark.parametrize(
    "code, env, expected",
    [
        ("import impedax", {"IMPEDAX_CPU_DEVICES": "1"}, 1),
        ("import impedax", {"IMPEDAX_CPU_DEVICES": "3"}, 3),
        ("import impedax", {"XLA_FLAGS": "--xla_force_host_platform_device_count=3"}, 3),
        ("import jax; jax.config.update('jax_num_cpu_devices', 3); import impedax", {}, 3),
        ("import jax; jax.numpy.ones(1).block_until_ready(); import impedax", {}, 1),  # JAX already ran
    ],
)
def test_the_users_choice_and_a_running_jax_are_left_alone(code, env, expected):
    assert devices_after(code, **env) == expected
