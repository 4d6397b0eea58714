"""Atomic output files (ngdgfric.files)."""

import os

import pytest

from ngdgfric.files import atomic_path, check_writable, write_csv, write_text


def test_a_failed_write_leaves_the_earlier_file_and_no_temporary(tmp_path):
    path = tmp_path / "table.csv"
    write_csv(path, [dict(a=1, b=2)])
    before = path.read_text()
    with pytest.raises(KeyboardInterrupt), atomic_path(path) as temporary:
        temporary.write_text("half a tab")
        raise KeyboardInterrupt
    assert path.read_text() == before == "a,b\n1,2\n"
    assert [p.name for p in tmp_path.iterdir()] == ["table.csv"]


def test_an_interrupt_as_the_temporary_file_is_made_leaves_none(tmp_path, monkeypatch):
    made = os.open

    def made_then_interrupted(*args, **kwargs):  # Ctrl-C or SIGTERM before the name is known to atomic_path
        os.close(made(*args, **kwargs))
        raise KeyboardInterrupt

    monkeypatch.setattr(os, "open", made_then_interrupted)
    with pytest.raises(KeyboardInterrupt):
        write_text(tmp_path / "table.md", "text")
    monkeypatch.undo()
    assert not list(tmp_path.iterdir())


def test_a_writer_that_writes_nothing_is_an_error(tmp_path):
    with pytest.raises(OSError, match="produced no file"), atomic_path(tmp_path / "x.vtu"):
        pass
    assert not list(tmp_path.iterdir())


def test_replacing_a_folder_is_an_error(tmp_path):
    (tmp_path / "x.md").mkdir()
    with pytest.raises(OSError, match="cannot write .*x.md"):
        write_text(tmp_path / "x.md", "text")


def test_columns_and_missing_folder(tmp_path):
    write_csv(tmp_path / "t.csv", [dict(a=1), dict(b=2, c=3)], fields=["a", "b"])
    assert (tmp_path / "t.csv").read_text().splitlines() == ["a,b", "1,", ",2"]
    check_writable(tmp_path / "new" / "folder")
    assert (tmp_path / "new" / "folder").is_dir()
    (tmp_path / "plain").write_text("")
    with pytest.raises(OSError, match="cannot write to the output folder"):
        check_writable(tmp_path / "plain" / "sub")
