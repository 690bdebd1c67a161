"""Atomic output: write to a temporary name next to the target, rename on success.

Every file and folder the package writes goes through this module, so that

- a failed command leaves no partial output and an existing output untouched;
- the final files have the modes of a plain ``open()`` / ``mkdir`` under the process umask
  (``0o666 & ~umask`` and ``0o777 & ~umask``; the temporary files of ``tempfile`` are 0600 / 0700);
- an error names the user's target path, never the temporary name.
"""

import contextlib
import json
import math
import os
import shutil
import tempfile

from .errors import PostprocessError


def _read_umask():
    """The process umask. os.umask can only be read by setting it, so it is read once, at import
    (before any thread of the package starts), and restored at once."""
    mask = os.umask(0o022)
    os.umask(mask)
    return mask


UMASK = _read_umask()
FILE_MODE = 0o666 & ~UMASK
DIR_MODE = 0o777 & ~UMASK


def _error(path, exc):
    """PostprocessError naming the user's ``path`` for an OSError on it or on its temporary."""
    reason = exc.strerror or str(exc)
    return PostprocessError(f"{path}: cannot write: {reason}")


def _is_ours(exc, tmp):
    """True when the OSError ``exc`` is about the temporary ``tmp`` (or a file inside it)."""
    names = [n for n in (getattr(exc, "filename", None), getattr(exc, "filename2", None)) if n]
    tmp = os.path.abspath(tmp)
    return any(os.path.abspath(str(n)) == tmp or os.path.abspath(str(n)).startswith(tmp + os.sep)
               for n in names)


def _parent(path):
    """Create the folder of ``path`` (modes under the umask); PostprocessError naming ``path``."""
    folder = os.path.dirname(os.path.abspath(path))
    try:
        os.makedirs(folder, exist_ok=True)
    except OSError as exc:
        raise PostprocessError(f"{path}: cannot create its folder {folder}: "
                               f"{exc.strerror or exc}") from None
    return folder


def check_file_target(path):
    """PostprocessError when ``path`` cannot become a file (it is a folder, or has no name)."""
    if not os.path.basename(str(path)):
        raise PostprocessError(f"{path}: an output file name is needed, not a folder")
    if os.path.isdir(path):
        raise PostprocessError(f"{path}: is a directory (an output file was expected)")


def _tmp_name(path, suffix=""):
    check_file_target(path)
    folder = _parent(path)
    try:
        fd, tmp = tempfile.mkstemp(prefix="." + os.path.basename(path) + ".",
                                   suffix=".tmp" + suffix, dir=folder)
    except OSError as exc:
        raise _error(path, exc) from None
    os.close(fd)
    return tmp


def _tmp_dir(path):
    if not os.path.basename(os.path.normpath(str(path))) or str(path).endswith(("/", os.sep)):
        raise PostprocessError(f"{path}: an output folder name is needed")
    if os.path.exists(path) and not os.path.isdir(path):
        raise PostprocessError(f"{path}: exists and is not a directory")
    parent = _parent(path)
    try:
        return tempfile.mkdtemp(prefix="." + os.path.basename(path) + ".", suffix=".tmp",
                                dir=parent)
    except OSError as exc:
        raise _error(path, exc) from None


def _set_modes(tmp, directory=False):
    """Give a finished temporary file (or folder tree) the modes of the umask."""
    if not directory:
        os.chmod(tmp, FILE_MODE)
        return
    os.chmod(tmp, DIR_MODE)
    for root, dirs, files in os.walk(tmp):
        for name in dirs:
            os.chmod(os.path.join(root, name), DIR_MODE)
        for name in files:
            os.chmod(os.path.join(root, name), FILE_MODE)


@contextlib.contextmanager
def atomic_path(path, suffix="", label=None):
    """Yield a temporary file name; on success it replaces ``path``, on failure it is removed.

    ``suffix`` lets writers that choose the format from the extension (matplotlib, meshio) see it.
    An OSError on the temporary (disk full, ``path`` is a folder, ...) is raised as a
    PostprocessError naming ``label`` (default ``path``): a file written inside a temporary
    folder is named by its final path.
    """
    label = path if label is None else label
    tmp = _tmp_name(path, suffix)
    try:
        try:
            yield tmp
            _set_modes(tmp)
            os.replace(tmp, path)
        except OSError as exc:
            if _is_ours(exc, tmp) or _is_ours(exc, path):
                raise _error(label, exc) from None
            raise
    except BaseException:
        with contextlib.suppress(OSError):
            os.remove(tmp)
        raise


def write_text(path, text):
    """Write ``text`` to ``path`` atomically."""
    with atomic_path(path) as tmp:
        with open(tmp, "w", encoding="utf-8") as handle:
            handle.write(text)


def strict_json_value(value):
    """``value`` with every NaN / infinite float replaced by None (JSON null = not available),
    recursively through dicts, lists and tuples; numpy scalars become Python numbers."""
    if isinstance(value, dict):
        return {str(k): strict_json_value(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [strict_json_value(v) for v in value]
    if hasattr(value, "item") and hasattr(value, "dtype"):        # numpy scalar or 0-d array
        value = value.item() if getattr(value, "ndim", 0) == 0 else value.tolist()
        return strict_json_value(value)
    if isinstance(value, float) and not math.isfinite(value):
        return None
    return value


def json_text(value, indent=2):
    """Strict JSON text (RFC 8259: no NaN / Infinity tokens) of ``value``; non-finite numbers
    become null (see strict_json_value)."""
    return json.dumps(strict_json_value(value), indent=indent, allow_nan=False) + "\n"


def write_json(path, value, indent=2):
    """Write ``value`` as strict JSON to ``path`` atomically (non-finite numbers -> null)."""
    write_text(path, json_text(value, indent))


@contextlib.contextmanager
def atomic_dir(path, replaceable=None):
    """Yield a temporary directory; on success it replaces the directory ``path``.

    ``replaceable(name) -> bool`` tells which entries of an existing ``path`` may be discarded;
    if the existing folder holds anything else, PostprocessError (before any work), so a folder
    of the user's is never replaced by mistake.
    """
    with Outputs() as outputs:
        yield outputs.directory(path, replaceable)


class Outputs:
    """Several outputs committed together (e.g. a .pvd and its folder of frames).

    ``file(path)`` and ``directory(path)`` return temporary names next to the targets; on a
    normal exit of the ``with`` block every temporary is renamed onto its target, on an
    exception (or if one rename fails) all temporaries are removed and the targets renamed so
    far are restored to their previous content. Errors name the user's paths.
    """

    def __init__(self):
        self.items = []        # (kind, target, tmp)

    def file(self, path, suffix=""):
        tmp = _tmp_name(path, suffix)
        self.items.append(("file", path, tmp))
        return tmp

    def directory(self, path, replaceable=None):
        if os.path.isdir(path) and replaceable is not None:
            foreign = sorted(n for n in os.listdir(path) if not replaceable(n))
            if foreign:
                raise PostprocessError(
                    f"{path}: the folder exists and holds {len(foreign)} entr"
                    f"{'y' if len(foreign) == 1 else 'ies'} that this command did not write "
                    f"(e.g. '{foreign[0]}'); remove it or choose another output name")
        tmp = _tmp_dir(path)
        self.items.append(("dir", path, tmp))
        return tmp

    def __enter__(self):
        return self

    def __exit__(self, kind, exc, tb):
        if kind is None:
            self.commit()
        else:
            self.abort()
        return False

    def abort(self):
        for kind, _, tmp in self.items:
            if kind == "dir":
                shutil.rmtree(tmp, ignore_errors=True)
            else:
                with contextlib.suppress(OSError):
                    os.remove(tmp)
        self.items = []

    def commit(self):
        done = []              # (target, backup or None)
        try:
            for kind, path, tmp in self.items:
                _set_modes(tmp, kind == "dir")
                backup = None
                try:
                    if os.path.lexists(path):
                        if kind == "file" and os.path.isdir(path):
                            raise PostprocessError(f"{path}: is a directory (an output file was "
                                                   f"expected)")
                        backup = tempfile.mktemp(prefix="." + os.path.basename(path) + ".",
                                                 suffix=".old",
                                                 dir=os.path.dirname(os.path.abspath(path)))
                        os.replace(path, backup)
                    try:
                        os.replace(tmp, path)
                    except OSError:
                        if backup:
                            os.replace(backup, path)
                        raise
                except OSError as exc:
                    raise _error(path, exc) from None
                done.append((path, backup))
        except BaseException:
            for path, backup in reversed(done):          # roll back what was renamed
                with contextlib.suppress(OSError):
                    if os.path.isdir(path) and not os.path.islink(path):
                        shutil.rmtree(path)
                    else:
                        os.remove(path)
                    if backup:
                        os.replace(backup, path)
            self.abort()
            raise
        for _, backup in done:
            if backup:
                if os.path.isdir(backup) and not os.path.islink(backup):
                    shutil.rmtree(backup, ignore_errors=True)
                else:
                    with contextlib.suppress(OSError):
                        os.remove(backup)
        self.items = []
