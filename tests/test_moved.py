"""Import paths of 0.1 that moved in 0.2 keep working for one release, each with a DeprecationWarning.

The old module paths are stub modules (``ngdgfric/newton.py``, ...): plain modules that warn and rebind their name
in ``sys.modules`` to the module at its new place, no import hook."""

import importlib
import os
import subprocess
import sys
from pathlib import Path

import pytest

import ngdgfric as ndf

# the subprocesses import the ngdgfric these tests import
SAME_PACKAGE = dict(os.environ, PYTHONPATH=str(Path(ndf.__file__).resolve().parents[1]))
# the promise of release 0.2: these paths of 0.1 work until 0.3
MOVED_MODULES = {
    **{name: f"ngdgfric.dg.{name}" for name in ("methods", "forms", "liftings", "material", "discretization")},
    **{name: f"ngdgfric.solvers.{name}" for name in (
        "newton", "fixed_point", "uzawa", "semismooth", "reduced", "condensation", "complementary_energy",
        "nonlinear", "pardiso", "options")},
    "traces": "ngdgfric.contact.traces",
}
MOVED_NAMES = {"refine": "ngdgfric.meshes", "minimum_angle": "ngdgfric.adaptivity", "HPState": "ngdgfric.hp"}


@pytest.mark.parametrize("old", sorted(MOVED_MODULES))
def test_an_old_module_path_is_the_module_at_its_new_place(old):
    sys.modules.pop(f"ngdgfric.{old}", None)
    with pytest.warns(DeprecationWarning, match=f"ngdgfric.{old} moved to {MOVED_MODULES[old]}"):
        module = importlib.import_module(f"ngdgfric.{old}")
    assert module is importlib.import_module(MOVED_MODULES[old])


@pytest.mark.parametrize("old", [*sorted(MOVED_MODULES), "linalg"])
def test_an_old_module_is_an_attribute_of_the_package_with_a_warning(old):
    sys.modules.pop(f"ngdgfric.{old}", None)
    vars(ndf).pop(old, None)  # bound by an earlier import of the old path
    with pytest.warns(DeprecationWarning, match=f"ngdgfric.{old} moved to"):
        module = getattr(ndf, old)
    assert module is sys.modules[f"ngdgfric.{old}"]


def test_linalg_has_the_names_of_sparse_and_threads():
    sys.modules.pop("ngdgfric.linalg", None)
    with pytest.warns(DeprecationWarning, match="ngdgfric.linalg moved"):
        from ngdgfric.linalg import BlockSum, limited_blas
    from ngdgfric.sparse import BlockSum as new_block_sum
    from ngdgfric.threads import limited_blas as new_limited_blas
    assert (BlockSum, limited_blas) == (new_block_sum, new_limited_blas)
    with pytest.raises(AttributeError, match="no attribute 'nothing'"):
        sys.modules["ngdgfric.linalg"].nothing  # noqa: B018


@pytest.mark.parametrize("name", sorted(MOVED_NAMES))
def test_a_name_that_left_the_top_level_still_resolves_with_a_warning(name):
    with pytest.warns(DeprecationWarning, match=f"ngdgfric.{name} moved"):
        value = getattr(ndf, name)
    assert value is getattr(importlib.import_module(MOVED_NAMES[name]), name)
    assert name not in ndf.__all__


def test_an_unknown_top_level_name_is_an_attribute_error():
    with pytest.raises(AttributeError, match="no attribute 'solv'"):
        ndf.solv  # noqa: B018


def test_the_public_api_is_all_of_it_and_the_method_table_is_read_only():
    assert all(hasattr(ndf, name) for name in ndf.__all__)
    assert ndf.__version__ == importlib.metadata.version("ngdgfric")
    with pytest.raises(TypeError):
        ndf.METHODS["mine"] = ndf.METHODS["sipg"]


def test_the_warnings_point_at_the_users_line_where_python_shows_them(tmp_path):
    # a DeprecationWarning shows by default only when attributed to __main__: the user's script, not the package
    script = tmp_path / "old_names.py"
    script.write_text("import ngdgfric\nngdgfric.refine\nngdgfric.uzawa\nimport ngdgfric.fixed_point\n")
    result = subprocess.run([sys.executable, str(script)], capture_output=True, text=True, timeout=120,
                            env=SAME_PACKAGE)
    assert result.returncode == 0, result.stderr
    shown = [line for line in result.stderr.splitlines() if "DeprecationWarning" in line]
    assert [line.split(": DeprecationWarning")[0] for line in shown] \
        == [f"{script}:2", f"{script}:3", f"{script}:4"], result.stderr

@pytest.mark.parametrize("how", ["-c", "-"])
def test_warnings_show_in_python_c_and_on_standard_input(how):
    # there __main__'s loader is BuiltinImporter: every package warning raised "ImportError: '__main__' is not a
    # built-in module" when warn_explicit was given the caller's globals
    code = "import ngdgfric\nngdgfric.refine\nimport warnings\nwarnings.warn('from the user', UserWarning)\n"
    argv, given = ([sys.executable, "-c", code], None) if how == "-c" else ([sys.executable, "-"], code)
    result = subprocess.run(argv, input=given, capture_output=True, text=True, timeout=120, env=SAME_PACKAGE)
    assert result.returncode == 0, result.stderr
    shown = [line.split(": ", 1)[0] for line in result.stderr.splitlines() if "Warning:" in line]
    assert len(shown) == 2 and shown[0].endswith(":2") and shown[0][:-2] == shown[1][:-2], result.stderr



def test_a_file_named_like_a_module_in_the_working_directory_does_not_break_meshing(tmp_path):
    # the mesh server's interpreter must not import the caller's signal.py instead of the standard library's
    work, scripts = tmp_path / "work", tmp_path / "scripts"
    work.mkdir(), scripts.mkdir()
    (work / "signal.py").write_text("raise ImportError('the wrong signal module')\n")
    (scripts / "mesh.py").write_text("import ngdgfric as ndf\nprint(ndf.netgen_mesh(ndf.example_6_1(), 0.5).ne > 0)\n")
    result = subprocess.run([sys.executable, str(scripts / "mesh.py")], cwd=work, capture_output=True, text=True,
                            timeout=120, env=SAME_PACKAGE)
    assert result.stdout.strip() == "True", result.stderr[-2000:]
