"""Output files written atomically: a temporary file in the target's folder, then a rename.

An interrupted or failed write leaves the previous file (or none) in place, never a truncated one.
"""

import contextlib
import csv
import os
import secrets
import tempfile
from pathlib import Path

__all__ = ["atomic_path", "write_text", "write_csv", "check_writable"]


@contextlib.contextmanager
def atomic_path(path):
    """Yield a temporary path beside ``path``; on success rename it to ``path``, else remove it.

    The temporary name keeps ``path``'s suffix, so writers that choose a format by the suffix, such
    as matplotlib's ``savefig``, write the right one.  OSError naming ``path`` if the writer
    produced no file or the rename fails.
    """
    path = Path(path)
    temporary = path.with_name(f".{path.name}.{secrets.token_hex(8)}{path.suffix}")
    try:  # made inside the try (not by tempfile.mkstemp): an interrupt right after it is made removes it too
        try:
            os.close(os.open(temporary, os.O_WRONLY | os.O_CREAT | os.O_EXCL, 0o600))
        except OSError as exc:
            if isinstance(exc, FileExistsError):  # another writer's file (the same 64 random bits): left alone
                temporary = None
            raise OSError(f"cannot write {path}: {exc.strerror or exc}") from exc
        temporary.unlink()  # the name is reserved; the writer must create the file (a writer failing silently is seen)
        yield temporary
        if not temporary.exists():
            raise OSError(f"could not write {path}: the writer produced no file")
        try:
            with open(temporary, "rb") as written:  # on disk before it replaces the earlier file
                os.fsync(written.fileno())
            os.replace(temporary, path)
        except OSError as exc:
            raise OSError(f"cannot write {path}: {exc.strerror or exc}") from exc
    finally:
        if temporary is not None:
            temporary.unlink(missing_ok=True)


def write_text(path, text):
    """Write ``text`` to ``path`` atomically."""
    with atomic_path(path) as temporary:
        temporary.write_text(text)


def write_csv(path, rows, fields=None):
    """Write the dicts ``rows`` as CSV atomically; columns ``fields`` (default: every key, in order of
    first appearance; keys not in ``fields`` are left out)."""
    fields = list(dict.fromkeys(k for row in rows for k in row)) if fields is None else fields
    with atomic_path(path) as temporary, open(temporary, "w", newline="") as handle:
        writer = csv.DictWriter(handle, fieldnames=fields, extrasaction="ignore")
        writer.writeheader()
        writer.writerows(rows)


def check_writable(folder):
    """Create ``folder`` if needed and check that a file can be written in it (OSError naming it if not)."""
    folder = Path(folder)
    try:
        folder.mkdir(parents=True, exist_ok=True)
        with tempfile.TemporaryFile(dir=folder):
            pass
    except OSError as exc:
        raise OSError(f"cannot write to the output folder {str(folder)!r}: {exc.strerror or exc}") from exc
