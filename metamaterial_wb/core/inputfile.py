"""Input files, checked (issue 19); the output side is :mod:`metamaterial_wb.core.fileio`.

* :func:`read_json` reads a JSON input file and fails with one :class:`SceneError` line for anything
  that is not a readable, regular, UTF-8 JSON file of sane depth and numbers (a directory, a symlink
  loop, a FIFO, non-UTF-8 bytes, 10^400, NaN, 900 levels of nesting, ...).
* :func:`read_text` reads a text input (a CSV table) under the same file checks.
* :func:`check_tree` is the same number / depth / unicode check for data that is already parsed
  (``Scene.from_dict`` calls it, so the GUI's dictionaries get it too).
"""
import errno
import json
import math
import os
import stat

from metamaterial_wb.core.errors import SceneError

MAX_INPUT_BYTES = 256 * 2 ** 20     # a scene of 4 M cells as a "cells" list is ~60 MB
MAX_DEPTH = 32                      # the deepest real scene field is ~6 levels
MAX_INT = 2 ** 63 - 1


class _HugeInt:
    """Placeholder for an integer literal too long to convert (Python refuses > 4300 digits)."""

    def __init__(self, text):
        self.digits = len(text.lstrip("-"))


def _parse_int(text):
    if len(text) > 40:
        return _HugeInt(text)
    return int(text)


def _fmt_path(parts):
    if len(parts) > 12:
        return _fmt_path(parts[:6]) + "..." + _fmt_path(parts[-2:]) + f" (depth {len(parts)})"
    out = ""
    for p in parts:
        out += f"[{p}]" if isinstance(p, int) else (f".{p}" if out else str(p))
    return out


def check_tree(data, root=""):
    """Refuse non-finite or huge numbers, unpaired surrogates and deep nesting anywhere in ``data``.

    Iterative (no recursion), so a structure nested 10^5 deep is reported, not a RecursionError.
    The error names the field, e.g. ``dynamics.integrator.dt_s: NaN is not a finite number``.

    Parameters
    ----------
    data : object
        The parsed JSON tree.
    root : str, optional
        Field path prefix for error messages.

    Raises
    ------
    SceneError
        On the first offending value.
    """
    isfinite = math.isfinite
    # stack entries: (container, depth, where) with where = (parent where, key) or None
    stack = [(data, 0, (None, root) if root else None)]

    def path_of(where, key=None):
        parts = [] if key is None else [key]
        while where is not None:
            where, k = where
            parts.append(k)
        return _fmt_path(parts[::-1])

    def bad_scalar(v, where, key):
        t = type(v)
        if t is int or isinstance(v, int):
            if isinstance(v, bool) or -MAX_INT <= v <= MAX_INT:
                return
            raise SceneError(path_of(where, key), f"{v:.3e} is too large (integers up to 2^63)")
        if t is float or isinstance(v, float):
            if not isfinite(v):
                raise SceneError(path_of(where, key), f"{v!r} is not a finite number (NaN, Infinity and "
                                                      f"numbers beyond 1.8e308 are not allowed)")
            if v != 0.0 and -2.2250738585072014e-308 < v < 2.2250738585072014e-308:
                raise SceneError(path_of(where, key), f"{v!r} is subnormal (too close to zero to compute with)")
            return
        if t is str:
            _check_str(v, path_of, where, key)
            return
        if v is None:
            return
        if t is _HugeInt:
            raise SceneError(path_of(where, key), f"an integer of {v.digits} digits is far too large")
        raise SceneError(path_of(where, key), f"{t.__name__} is not a JSON value")

    if not isinstance(data, (dict, list, tuple)):
        bad_scalar(data, None, root or None)
        return
    while stack:
        obj, depth, where = stack.pop()
        if depth > MAX_DEPTH:
            raise SceneError(path_of(where), f"too deeply nested (more than {MAX_DEPTH} levels)")
        if type(obj) is list and len(obj) > 16 and _bulk_ok(obj, depth):
            continue
        items = obj.items() if isinstance(obj, dict) else enumerate(obj)
        for k, v in items:
            t = type(v)
            if t is dict or t is list or t is tuple or isinstance(v, (dict, list, tuple)):
                stack.append((v, depth + 1, (where, k)))
            elif t is int:
                if not -MAX_INT <= v <= MAX_INT:
                    bad_scalar(v, where, k)
            elif t is float:
                if not isfinite(v) or (v != 0.0 and -2.2250738585072014e-308 < v < 2.2250738585072014e-308):
                    bad_scalar(v, where, k)
            elif t is not bool and v is not None:
                bad_scalar(v, where, k)
            if type(k) is not int:
                if type(k) is not str:
                    raise SceneError(path_of(where), f"key {k!r} is not a string")
                _check_str(k, path_of, where, k)


def _ints_ok(values):
    return not values or (min(values) >= -MAX_INT and max(values) <= MAX_INT)


def _bulk_ok(obj, depth):
    """True when a long list is all plain ints in range, or all lists of such ints (the common big
    case: ``layout.cells``), checked at C speed; False means: look at each item."""
    import itertools

    types = set(map(type, obj))
    if types <= {int, bool}:
        return _ints_ok(obj)
    if types == {str}:
        return all(map(str.isascii, obj))
    if types == {list} and depth + 2 <= MAX_DEPTH:
        flat = list(itertools.chain.from_iterable(obj))
        return set(map(type, flat)) <= {int, bool} and _ints_ok(flat)
    return False


def _check_str(s, path_of, where, key):
    if s.isascii():
        return
    try:
        s.encode("utf-8")
    except UnicodeEncodeError as exc:
        raise SceneError(path_of(where, key), f"text contains an unpaired surrogate at position {exc.start} "
                                              f"(not valid Unicode)") from None


def _stat_input(path, what):
    if not isinstance(path, str) or path == "":
        raise SceneError(what, "no file name given")
    if "\x00" in path:
        raise SceneError(what, f"{path!r} contains a NUL character")
    try:
        st = os.stat(path)
    except OSError as exc:
        raise SceneError(what, f"{path}: {os_reason(exc)}") from None
    if stat.S_ISDIR(st.st_mode):
        raise SceneError(what, f"{path} is a directory, not a file")
    if not stat.S_ISREG(st.st_mode):
        raise SceneError(what, f"{path} is not a regular file ({file_kind(st.st_mode)})")
    if st.st_size > MAX_INPUT_BYTES:
        raise SceneError(what, f"{path} has {st.st_size} bytes; at most {MAX_INPUT_BYTES} are read")
    return st


def os_reason(exc):
    """The reason of an ``OSError`` in words (``file not found``, ``permission denied``, ...).

    Parameters
    ----------
    exc : OSError

    Returns
    -------
    str
    """
    return {errno.ENOENT: "file not found", errno.ELOOP: "symlink loop (too many levels of symbolic links)",
            errno.ENOTDIR: "a part of the path is a file, not a folder", errno.EACCES: "permission denied",
            errno.ENAMETOOLONG: "file name too long", errno.EISDIR: "is a directory"}.get(
        exc.errno, exc.strerror or str(exc))


def file_kind(mode):
    """What a file of ``st_mode`` ``mode`` that is no regular file is, in words (``a FIFO``, ``a directory``, ...).

    Parameters
    ----------
    mode : int
        ``os.stat(...).st_mode``.

    Returns
    -------
    str
    """
    for test, name in ((stat.S_ISFIFO, "a FIFO"), (stat.S_ISCHR, "a character device"),
                       (stat.S_ISBLK, "a block device"), (stat.S_ISSOCK, "a socket"), (stat.S_ISDIR, "a directory")):
        if test(mode):
            return name
    return "a special file"


def read_text(path, what="input"):
    """The text of a regular UTF-8 file, or a SceneError naming ``what`` and the reason. ``path``: a str
    or an ``os.PathLike`` (pathlib.Path).

    Parameters
    ----------
    path : str or os.PathLike
    what : str, optional
        What the file is, for error messages.

    Returns
    -------
    str

    Raises
    ------
    SceneError
        If the file is missing, not a regular file, too big or not UTF-8.
    """
    if isinstance(path, os.PathLike):
        path = os.fspath(path)
    _stat_input(path, what)
    try:
        with open(path, "rb") as f:
            raw = f.read(MAX_INPUT_BYTES + 1)
    except OSError as exc:
        raise SceneError(what, f"{path}: {os_reason(exc)}") from None
    if len(raw) > MAX_INPUT_BYTES:
        raise SceneError(what, f"{path} has more than {MAX_INPUT_BYTES} bytes")
    try:
        text = raw.decode("utf-8-sig")
    except UnicodeDecodeError as exc:
        raise SceneError(what, f"{path} is not UTF-8 text (byte 0x{raw[exc.start]:02x} at offset {exc.start})") \
            from None
    return text


class _DuplicateKey(ValueError):
    pass


def _unique_keys(pairs):
    d = dict(pairs)
    if len(d) != len(pairs):
        seen = set()
        for k, _ in pairs:
            if k in seen:
                raise _DuplicateKey(k[:60])
            seen.add(k)
    return d


def parse_json(text, what=""):
    """``json.loads`` that never raises anything but a one-line SceneError (then :func:`check_tree`).

    Parameters
    ----------
    text : str
    what : str, optional
        What the text is, for error messages.

    Returns
    -------
    object
        The parsed, checked tree.

    Raises
    ------
    SceneError
    """
    try:
        data = json.loads(text, parse_int=_parse_int, object_pairs_hook=_unique_keys)
    except _DuplicateKey as exc:
        raise SceneError(what, f"{exc.args[0]!r} is given twice in one JSON object (the later value would "
                               "silently win); give each key once") from None
    except RecursionError:
        raise SceneError(what, f"too deeply nested (more than {MAX_DEPTH} levels)") from None
    except json.JSONDecodeError as exc:
        raise SceneError(what, f"not a JSON file (not valid JSON: {exc.msg}) at line {exc.lineno} "
                               f"column {exc.colno}") from None
    except ValueError as exc:  # e.g. Python's integer-digit limit
        raise SceneError(what, f"not a JSON file: {exc}") from None
    check_tree(data, "")
    return data


def read_json(path, what="input"):
    """Read and check a JSON file (see module doc). Field names in errors get ``(in PATH)``.

    Parameters
    ----------
    path : str or os.PathLike
    what : str, optional
        What the file is, for error messages.

    Returns
    -------
    object
        The parsed, checked tree.

    Raises
    ------
    SceneError
    """
    if isinstance(path, os.PathLike):
        path = os.fspath(path)
    text = read_text(path, what)
    try:
        return parse_json(text, "")
    except SceneError as exc:
        raise SceneError(exc.field or what, f"{exc.message} (in {path})") from None
