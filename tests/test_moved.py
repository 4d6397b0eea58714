"""Import paths of 0.1 that moved in 0.2 keep working for one release, each with a DeprecationWarning."""

import importlib
import sys

import pytest

import ngdgfric as ndf
from ngdgfric import _moved


@pytest.mark.parametrize("old", sorted(_moved.MOVED_MODULES))
def test_an_old_module_path_is_the_module_at_its_new_place(old):
    sys.modules.pop(f"ngdgfric.{old}", None)
    with pytest.warns(DeprecationWarning, match=f"ngdgfric.{old} moved to {_moved.MOVED_MODULES[old]}"):
        module = importlib.import_module(f"ngdgfric.{old}")
    assert module is importlib.import_module(_moved.MOVED_MODULES[old])


def test_linalg_has_the_names_of_sparse_and_threads():
    sys.modules.pop("ngdgfric.linalg", None)
    with pytest.warns(DeprecationWarning, match="ngdgfric.linalg moved"):
        from ngdgfric.linalg import BlockSum, limited_blas
    from ngdgfric.sparse import BlockSum as new_block_sum
    from ngdgfric.threads import limited_blas as new_limited_blas
    assert (BlockSum, limited_blas) == (new_block_sum, new_limited_blas)
    with pytest.raises(AttributeError, match="no attribute 'nothing'"):
        sys.modules["ngdgfric.linalg"].nothing  # noqa: B018


@pytest.mark.parametrize("name", sorted(_moved.MOVED_NAMES))
def test_a_name_that_left_the_top_level_still_resolves_with_a_warning(name):
    with pytest.warns(DeprecationWarning, match=f"ngdgfric.{name} moved"):
        value = getattr(ndf, name)
    assert value is getattr(importlib.import_module(_moved.MOVED_NAMES[name]), name)
    assert name not in ndf.__all__


def test_an_unknown_top_level_name_is_an_attribute_error():
    with pytest.raises(AttributeError, match="no attribute 'solv'"):
        ndf.solv  # noqa: B018


def test_the_public_api_is_all_of_it_and_the_method_table_is_read_only():
    assert all(hasattr(ndf, name) for name in ndf.__all__)
    assert ndf.__version__ == importlib.metadata.version("ngdgfric")
    with pytest.raises(TypeError):
        ndf.METHODS["mine"] = ndf.METHODS["sipg"]
