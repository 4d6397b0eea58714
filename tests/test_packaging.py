"""The package as a user gets it: ``python -m build`` makes a wheel and an sdist, and the wheel installed in a fresh
venv passes the quick tests.

The fresh venv gets the wheel by pip (``--no-deps``) and its dependencies from this environment's site-packages as a
plain path entry (so that the editable install of this checkout, a ``.pth`` hook there, is not run): the tests then
import the installed ngdgfric, not this checkout's (they run from its root with ``PYTHONSAFEPATH``), and run offline
in about the time of the quick subset.  The
dependencies themselves are installed from the same metadata by the README's command.
"""

import email.parser
import os
import subprocess
import sys
import sysconfig
import tarfile
import venv
import zipfile
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parent.parent
DATA = sorted(path.name for path in (ROOT / "ngdgfric" / "data").glob("*.toml"))

pytestmark = pytest.mark.slow


@pytest.fixture(scope="module")
def dist(tmp_path_factory):
    """The folder with the wheel and the sdist of ``python -m build`` (an isolated build, as pip does it)."""
    out = tmp_path_factory.mktemp("dist")
    done = subprocess.run([sys.executable, "-m", "build", "--outdir", str(out), str(ROOT)], capture_output=True,
                          text=True, timeout=900)
    assert done.returncode == 0, done.stdout[-3000:] + done.stderr[-3000:]
    return out


def test_the_wheel_holds_the_package_its_data_licence_and_metadata(dist):
    wheel = zipfile.ZipFile(next(dist.glob("ngdgfric-*.whl")))
    names = wheel.namelist()
    assert sorted(Path(name).name for name in names if name.startswith("ngdgfric/data/")) == DATA
    assert any(name.endswith(".dist-info/licenses/LICENSE") for name in names)
    metadata = email.parser.Parser().parsestr(wheel.read(next(n for n in names if n.endswith(".dist-info/METADATA")))
                                              .decode())
    assert metadata["License-Expression"] == "MIT" or metadata["License"] == "MIT"
    assert metadata["Requires-Python"] == ">=3.10"
    assert metadata["Description-Content-Type"] == "text/markdown"
    assert metadata.get_payload().strip() == (ROOT / "README.md").read_text(encoding="utf-8").strip()
    assert "Programming Language :: Python :: 3.11" in metadata.get_all("Classifier")
    assert "https://arxiv.org/abs/2104.08266" in " ".join(metadata.get_all("Project-URL"))
    assert {"ngsolve", "numpy", "matplotlib"} <= {r.split(";")[0].split()[0] for r in metadata.get_all("Requires-Dist")}


def test_the_sdist_holds_what_a_packager_needs(dist):
    with tarfile.open(next(dist.glob("ngdgfric-*.tar.gz"))) as sdist:
        names = {Path(*Path(name).parts[1:]).as_posix() for name in sdist.getnames()}
    assert {"LICENSE", "CITATION.cff", "README.md", "setup.py", "pytest.ini"} <= names
    assert {f"ngdgfric/data/{name}" for name in DATA} <= names


def test_the_wheel_in_a_fresh_venv_passes_the_quick_tests(dist, tmp_path):
    home = tmp_path / "venv"
    venv.create(home, with_pip=True)
    python = home / "bin" / "python"
    site = Path(subprocess.check_output([python, "-c", "import sysconfig; print(sysconfig.get_paths()['purelib'])"],
                                        text=True).strip())
    (site / "dependencies.pth").write_text(sysconfig.get_paths()["purelib"] + "\n")  # a path, its .pth files not run
    install = subprocess.run([python, "-m", "pip", "install", "--no-deps", "--no-index", "--quiet",
                              str(next(dist.glob("ngdgfric-*.whl")))], capture_output=True, text=True, timeout=600)
    assert install.returncode == 0, install.stderr[-3000:]
    # from the checkout's root (the tests read its results/ and docs/), which must not shadow the installed package:
    # PYTHONSAFEPATH keeps the working directory off sys.path
    environment = dict(os.environ, PYTHONSAFEPATH="1")
    where = subprocess.check_output([python, "-c", "import ngdgfric; print(ngdgfric.__file__)"], text=True, cwd=ROOT,
                                    env=environment)
    assert Path(where.strip()).is_relative_to(site), where  # the installed package, not this checkout
    version = subprocess.run([home / "bin" / "ngdgfric", "--version"], capture_output=True, text=True,
                             timeout=120)
    assert version.returncode == 0 and version.stdout.startswith("ngdgfric 0.2.0"), version.stdout + version.stderr
    tests = subprocess.run([python, "-m", "pytest", "-q", "-x", "-m", "not slow", "-p", "no:cacheprovider", "tests"],
                           capture_output=True, text=True, cwd=ROOT, env=environment, timeout=3000)
    assert tests.returncode == 0, tests.stdout[-5000:] + tests.stderr[-2000:]
