"""cmake --install (component python) puts a working package into the site-packages directory
of a prefix, independent of the build tree."""
import os
import subprocess
import sys

import pytest

BUILD = os.environ.get("HBF_BUILD_DIR")
CMAKE = os.environ.get("CMAKE_COMMAND", "cmake")


@pytest.mark.skipif(not BUILD, reason="HBF_BUILD_DIR not set (run through ctest)")
def test_the_installed_package_works_alone(tmp_path):
    prefix = tmp_path / "prefix"
    r = subprocess.run([CMAKE, "--install", BUILD, "--component", "python", "--prefix", str(prefix)],
                       capture_output=True, text=True)
    assert r.returncode == 0, r.stderr
    sites = [os.path.join(d, "hbfriction") for d, dirs, _ in os.walk(prefix) if "hbfriction" in dirs]
    assert len(sites) == 1 and sites[0].endswith(("site-packages/hbfriction", "dist-packages/hbfriction"))
    assert sorted(f for f in os.listdir(sites[0]) if not f.startswith("_core")) == ["__init__.py", "_build.py"]
    env = {k: v for k, v in os.environ.items() if k != "PYTHONPATH"}
    env["PYTHONPATH"] = os.path.dirname(sites[0])
    code = ("import hbfriction; b = hbfriction.frf(hbfriction.absorber('lugre'), wmin=1.0, wmax=1.1); "
            "print(hbfriction.__file__); print(b.status, len(b))")
    r = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, env=env, cwd=tmp_path)
    assert r.returncode == 0, r.stderr
    where, result = r.stdout.splitlines()
    assert where.startswith(str(prefix)) and result.startswith("completed")
