"""Files out, safely (issue 19); inputs are read by :mod:`metamaterial_wb.core.inputfile`.

* :func:`check_output` checks an output path before any work is done.
* :func:`write_atomic` / :func:`write_json` write one file through a temporary file and a rename; a path that
  is a symbolic link is written through to the file it points to (:func:`write_target`), as ``cp`` does;
  :class:`OutputSet` moves a whole set of files into a folder, rolling back if any move fails. The folders a
  failed write created are removed again (:mod:`metamaterial_wb.core.outdir`, re-exported here, with the helpers
  for an output folder's earlier files).
* Temporary names carry the writer's process id (``.tmp-<pid>-...``); :func:`sweep_stale` removes
  those of processes that no longer run (a ``kill -9`` leaves them), and is called on every write
  (and by the STEP writer on the system temporary folder, for its ``.mmwb-<pid>-*.step`` files).
"""
import json
import os
import re
import shutil
import stat
import tempfile

from metamaterial_wb.core.errors import SceneError
from metamaterial_wb.core.inputfile import file_kind, os_reason
from metamaterial_wb.core.outdir import (_same_file, check_scene_not_output, earlier_outputs,  # noqa: F401 (re-exported)
                                         make_dirs, missing_dirs, remove_new_dirs, remove_outputs)

# Every kind of temporary name (``.KIND-<pid>-...``) a writer may use: :func:`temp_prefix` refuses any other, so
# :func:`sweep_stale` (whose pattern is made from this list) knows every folder / file a killed writer can leave.
TEMP_KINDS = ("tmp", "tmp-solve", "tmp-simulate", "build", "sleeve", "sleeve-export", "mm-export", "mmwb")
TEMP_PREFIXES = tuple(f".{k}-" for k in TEMP_KINDS)
_STALE_RE = re.compile(r"^\.(?:%s)-([0-9]{1,10})-"      # ASCII digits; longer is no process id
                       % "|".join(re.escape(k) for k in sorted(TEMP_KINDS, key=len, reverse=True)))
_KERNEL_FS = ("/proc", "/sys", "/dev")


# ----------------------------------------------------------------------------------------------
# output
# ----------------------------------------------------------------------------------------------
def check_output(path, kind="file", option="--out", inputs=()):
    """Check an output path before any work: ``kind`` is "file" or "dir". Returns the absolute path.

    Refused: an empty name, a NUL, a file name ending in a path separator or in ``.`` / ``..`` (it names a
    folder), a path under /proc, /sys or /dev, a name longer than 255 bytes or a
    path longer than 4095, an existing entry of another kind (a directory for a file, a FIFO, a
    device, a symlink loop), a parent that is a file, a folder that cannot be written, and a file that is
    one of the command's ``inputs`` (the same file, also through a link: it would be overwritten).

    Parameters
    ----------
    path : str or os.PathLike
    kind : str, optional
        ``"file"`` or ``"dir"``.
    option : str, optional
        The option name used in error messages.
    inputs : sequence of (str, str), optional
        ``(what, path)`` of the files the command reads (``None`` paths are skipped).

    Returns
    -------
    str
        The absolute path.

    Raises
    ------
    SceneError
        If the path is refused.
    """
    if not isinstance(path, str) or path.strip() == "":
        raise SceneError(option, "empty path; give a file or folder name")
    if "\x00" in path:
        raise SceneError(option, f"{path!r} contains a NUL character")
    if kind == "file":
        _check_file_name(path, option)
    ab = os.path.abspath(path)
    if len(os.fsencode(ab)) > 4095:
        raise SceneError(option, f"path of {len(os.fsencode(ab))} bytes is longer than the limit of 4095")
    for part in ab.split(os.sep):
        if len(os.fsencode(part)) > 255:
            raise SceneError(option, f"name {part[:20]}... has {len(os.fsencode(part))} bytes; at most 255 "
                                     f"are allowed")
    try:
        real = os.path.realpath(ab, strict=False)
    except OSError:
        real = ab
    for p in (ab, real):
        if any(p == k or p.startswith(k + os.sep) for k in _KERNEL_FS):
            raise SceneError(option, f"{path} is under {p.split(os.sep)[1] and '/' + p.split(os.sep)[1]}, a "
                                     f"kernel file system; choose a normal folder")
    try:
        st = os.stat(ab)
    except FileNotFoundError:
        st = None
    except OSError as exc:
        raise SceneError(option, f"{path}: {os_reason(exc)}") from None
    if st is None and kind != "file" and os.path.islink(ab):
        raise SceneError(option, f"{path} is a dangling symbolic link")
    if st is not None:
        if kind == "dir" and not stat.S_ISDIR(st.st_mode):
            what = "a file" if stat.S_ISREG(st.st_mode) else file_kind(st.st_mode)
            raise SceneError(option, f"{path} exists and is {what}, not a folder")
        if kind == "file" and not stat.S_ISREG(st.st_mode):
            raise SceneError(option, f"{path} exists and is {file_kind(st.st_mode)}, not a file; it is not replaced")
    # a file through a link (a dangling one too, if its target's folder exists): the file it points to is written,
    # in its own folder
    target = write_target(ab, option) if kind == "file" else ab
    anc = ab if (st is not None and kind == "dir") else os.path.dirname(target)
    while True:
        try:
            ast = os.stat(anc)
            break
        except FileNotFoundError:
            if os.path.islink(anc):
                raise SceneError(option, f"{anc} is a dangling symbolic link") from None
            anc = os.path.dirname(anc)
        except OSError as exc:
            raise SceneError(option, f"{anc}: {os_reason(exc)}") from None
    if not stat.S_ISDIR(ast.st_mode):
        raise SceneError(option, f"{anc} is {'a file' if stat.S_ISREG(ast.st_mode) else file_kind(ast.st_mode)}, "
                                 f"not a folder, so {path} cannot be created")
    if not os.access(anc, os.W_OK | os.X_OK) or (os.statvfs(anc).f_flag & os.ST_RDONLY):
        raise SceneError(option, f"folder {anc} is not writable")
    if st is not None and kind == "file":
        for what, inp in inputs:
            if _same_file(ab, inp):
                where = "" if os.path.abspath(inp) == ab else f" ({inp})"
                raise SceneError(option, f"{path} is the {what} this command reads{where}; it would be overwritten: "
                                         f"choose another file")
    return ab


def _check_file_name(path, option):
    """Refuse a file output whose last part names a folder: a trailing separator (``out/keep.txt/``, which
    ``os.path.abspath`` would strip, replacing keep.txt) or a last part ``.`` / ``..``, as POSIX reads them."""
    seps = tuple(s for s in (os.sep, os.altsep) if s)
    if path.endswith(seps):
        raise SceneError(option, f"{path} ends in {path[-1]!r}, so it names a folder; give a file name")
    last = path
    for s in seps[1:]:
        last = last.replace(s, os.sep)
    last = last.rsplit(os.sep, 1)[-1]
    if last in (".", ".."):
        raise SceneError(option, f"{path} ends in {last!r}, so it names a folder; give a file name")


def _pid_alive(pid):
    if pid == os.getpid():
        return True
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except (OSError, OverflowError):      # not ours to judge (no permission, or no such process id): keep it
        return True
    return True


def sweep_stale(folder):
    """Remove temporary files / folders left in ``folder`` by writers that no longer run (kill -9).

    Parameters
    ----------
    folder : str
    """
    try:
        names = os.listdir(folder)
    except OSError:
        return
    for n in names:
        m = _STALE_RE.match(n)
        if not m or _pid_alive(int(m.group(1))):
            continue
        p = os.path.join(folder, n)
        try:
            if os.path.isdir(p) and not os.path.islink(p):
                shutil.rmtree(p, ignore_errors=True)
            else:
                os.unlink(p)
        except OSError:
            pass


def temp_prefix(kind="tmp"):
    """The name prefix ``.KIND-<pid>-`` of this process's temporary files.

    Parameters
    ----------
    kind : str, optional
        One of :data:`TEMP_KINDS` (the kinds :func:`sweep_stale` recognises); a ValueError otherwise, so a
        new kind cannot be added without the sweep knowing it.

    Returns
    -------
    str
    """
    if kind not in TEMP_KINDS:
        raise ValueError(f"temporary kind {kind!r} is not in fileio.TEMP_KINDS {TEMP_KINDS}; add it there so "
                         f"sweep_stale removes what a killed writer leaves")
    return f".{kind}-{os.getpid()}-"


def make_temp_dir(parent, kind="tmp"):
    """A fresh temporary folder in ``parent`` named ``.KIND-<pid>-...`` (stale ones are swept first).

    Parameters
    ----------
    parent : str
    kind : str, optional

    Returns
    -------
    str
        The new folder's path.
    """
    sweep_stale(parent)
    try:
        return tempfile.mkdtemp(dir=parent, prefix=temp_prefix(kind))
    except OSError as exc:
        raise _named_error(exc, parent) from exc


def write_target(path, option="--out"):
    """The file a write of ``path`` replaces: ``path`` itself, or, when it is a symbolic link, the file the link
    points to (``os.path.realpath``), as ``cp`` and editors write through a link (the atomic rename would replace
    the link itself by a regular file). A dangling link gives its target when the target's folder exists.

    Parameters
    ----------
    path : str or os.PathLike
        The output path as given (absolute or relative).
    option : str, optional
        The option name used in error messages.

    Returns
    -------
    str
        ``path``, or the absolute path of the link's target.

    Raises
    ------
    SceneError
        ``path`` is a dangling link whose target's folder does not exist, or a link loop (naming the link and
        its target, under ``option``).
    """
    path = os.fspath(path)
    if not os.path.islink(path):
        return path
    target = os.path.realpath(path)
    if os.path.islink(target):              # realpath stops at a loop: the link it ends on is no file to write
        raise SceneError(option, f"{path} is a symbolic link loop ({target}); it is not replaced")
    folder = os.path.dirname(target)
    if not os.path.isdir(folder):
        raise SceneError(option, f"{path} is a symbolic link to {os.readlink(path)}, whose folder {folder} is not an "
                                 f"existing folder; create it, or write elsewhere")
    return target


def _shown_path(path):
    """``path`` as the user knows it: this process's temporary folders in it (``.KIND-<pid>-...``, where a set is
    written before it is moved in) left out, so ``OUT/.build-123-x/a.step`` is ``OUT/a.step``."""
    own = tuple(f"{p}{os.getpid()}-" for p in TEMP_PREFIXES)
    return os.sep.join(p for p in os.fspath(path).split(os.sep) if not p.startswith(own)) or os.sep


def _named_error(exc, path):
    """The OSError ``exc`` of writing ``path`` as one of the same errno (so of the same subclass) naming the file
    (:func:`_shown_path`): a write that fills the disk raises ``No space left on device`` with no file name, and the
    CLI prints the name an OSError carries."""
    return OSError(exc.errno, exc.strerror or str(exc), _shown_path(path))


def _mkdirs(folder):
    """``folder`` created with its parents; returns those created, innermost first (:func:`outdir.make_dirs`)."""
    return make_dirs(folder, "--out")


class _Sink:
    """The file a callable writer of :func:`write_atomic` gets: the open file, until the writer fails (:meth:`drop`);
    from then on writes, seeks and flushes go nowhere (only a position is kept). What the writer left open on the
    failed file (``np.savez``'s ZipFile, whose ``__del__`` writes a zip's directory to the file after it was closed)
    ends quietly: no traceback ``Exception ignored in ... ZipFile.__del__`` after the error."""

    def __init__(self, f):
        self._f, self._pos = f, None

    def drop(self):
        self._pos = 0

    def __getattr__(self, name):
        return getattr(self._f, name)

    def write(self, data):
        if self._pos is None:
            return self._f.write(data)
        self._pos += len(data)
        return len(data)

    def seek(self, offset, whence=0):
        if self._pos is None:
            return self._f.seek(offset, whence)
        self._pos = max(0, offset + (self._pos if whence == 1 else 0))
        return self._pos

    def tell(self):
        return self._f.tell() if self._pos is None else self._pos

    def flush(self):
        return self._f.flush() if self._pos is None else None

    def truncate(self, size=None):
        return self._f.truncate(size) if self._pos is None else self._pos


def write_atomic(path, data, mode="w"):
    """Write ``data`` (str or bytes, or a callable that writes to the open file) to ``path`` through a
    temporary file and a rename; the file gets the usual permissions (0666 less the umask). A ``path`` that is a
    symbolic link is written through: the file it points to is replaced, the link stays (:func:`write_target`).

    Parameters
    ----------
    path : str
    data : str, bytes or callable
    mode : str, optional
        ``"w"`` (text, UTF-8) or ``"wb"``.

    Raises
    ------
    OSError
        If writing fails (the temporary file is removed; ``path`` is untouched), naming ``path`` as the user knows
        it (:func:`_named_error`; ``f.write`` on a full disk names no file).
    SceneError
        ``path`` is a link that cannot be written through (:func:`write_target`).
    """
    path = write_target(os.path.abspath(os.fspath(path)))
    folder = os.path.dirname(path)
    made = _mkdirs(folder)          # removed again (if still empty) when the write fails
    tmp = None
    try:
        sweep_stale(folder)
        fd, tmp = tempfile.mkstemp(dir=folder, prefix=temp_prefix(), suffix="-" + os.path.basename(path)[-40:])
        with os.fdopen(fd, mode, **({"encoding": "utf-8"} if "b" not in mode else {})) as f:
            if callable(data):
                sink = _Sink(f)
                try:
                    data(sink)
                except BaseException:
                    sink.drop()
                    raise
            else:
                f.write(data)
        umask = os.umask(0)
        os.umask(umask)
        os.chmod(tmp, 0o666 & ~umask)  # mkstemp creates 0600; give the file normal permissions
        os.replace(tmp, path)
    except BaseException as exc:
        if tmp is not None and os.path.lexists(tmp):
            os.unlink(tmp)
        remove_new_dirs(made)
        if isinstance(exc, OSError) and (tmp is None or exc.filename in (None, tmp, path)):  # not another file's
            raise _named_error(exc, path) from exc
        raise


def write_json(path, obj, indent=1):
    """Serialise ``obj`` completely first, then write it atomically.

    Parameters
    ----------
    path : str
    obj : object
        JSON-serialisable (NaN / infinity refused).
    indent : int, optional

    Raises
    ------
    ValueError, TypeError
        If ``obj`` cannot be serialised (nothing is written).
    """
    text = json.dumps(obj, indent=indent, allow_nan=False) + "\n"
    write_atomic(path, text)


class OutputSet:
    """Write a set of files into ``out_dir`` all together or not at all.

    ``with OutputSet(out_dir, kind) as tmp:`` gives a temporary folder inside ``out_dir``; write the
    files there. On a clean exit every entry is moved into ``out_dir`` (replacing older ones); if a
    move fails the entries already moved are put back and the older ones restored. On any exception
    (also KeyboardInterrupt / SIGTERM through the CLI) the temporary folder is removed, and so are the folders
    ``__enter__`` created (``out_dir`` and its parents) when they are empty.
    """

    def __init__(self, out_dir, kind="tmp"):
        self.out_dir = os.path.abspath(out_dir)
        self.kind = kind
        self.tmp = None
        self.names = []
        self.made = []

    def __enter__(self):
        self.made = _mkdirs(self.out_dir)
        try:
            self.tmp = make_temp_dir(self.out_dir, self.kind)
        except BaseException:
            remove_new_dirs(self.made)
            raise
        return self.tmp

    def __exit__(self, et, ev, tb):
        done = False
        try:
            if et is None:
                self.names = self._commit()
                done = True
        finally:
            shutil.rmtree(self.tmp, ignore_errors=True)
            if not done:
                remove_new_dirs(self.made)
        return False

    def _commit(self):
        names = sorted(os.listdir(self.tmp))
        commit_set(self.tmp, self.out_dir, names)
        return names


def commit_set(tmp, out_dir, names):
    """Move ``names`` from folder ``tmp`` into ``out_dir`` all together: if one move fails, the ones
    already moved are taken back and the files they replaced restored, then the error is raised.

    A new file whose destination is a symbolic link to a file (or a dangling one) is written through, as
    :func:`write_atomic` writes: the file the link points to is replaced and the link stays; one in another folder
    is first moved beside it (into a temporary folder there, so that the moves stay renames on one file system). A
    link to a folder, or one where a folder goes, is replaced as any entry is.

    Parameters
    ----------
    tmp : str
        The folder holding the new files.
    out_dir : str
        The destination folder.
    names : sequence of str
        File names inside ``tmp``.

    Raises
    ------
    SceneError
        An entry of ``out_dir`` is of another kind than the new one (a folder where a file goes, or a file
        where a folder goes), or ``names`` holds one name twice (also in another letter case: one file on
        Windows and macOS; the second move would save the first one's new file as the "earlier" one, and a
        rollback would restore it), or two names are one file through a link, or a link cannot be written through
        (:func:`write_target`): nothing is moved.
    OSError
        The first failed move (after rolling back), naming its file (:func:`_named_error`).
    """
    seen = {}
    for n in names:
        if n.casefold() in seen:
            raise SceneError("--out", f"this run would write {n} twice ({seen[n.casefold()]} and {n}); nothing was "
                                      f"moved into {out_dir}")
        seen[n.casefold()] = n
    dests, real = {}, {}
    for n in names:     # before any move: an entry of another kind is the user's, never ours to replace
        dst = os.path.join(out_dir, n)
        new_dir = os.path.isdir(os.path.join(tmp, n))
        if os.path.lexists(dst) and not os.path.islink(dst) and os.path.isdir(dst) != new_dir:
            what = "a folder" if os.path.isdir(dst) else "a file"
            raise SceneError("--out", f"{dst} exists and is {what}; it is not replaced (this run writes "
                                      f"{'a folder' if new_dir else 'a file'} of that name): move it or choose "
                                      f"another output folder")
        if os.path.islink(dst) and not new_dir and (os.path.isfile(dst) or not os.path.exists(dst)):
            dst = write_target(dst)             # a file over a link: the file it points to
        key = os.path.realpath(dst)
        if key in real:
            raise SceneError("--out", f"{os.path.join(out_dir, real[key])} and {n} in {out_dir} are one file "
                                      f"({key}) through a symbolic link, and this run writes both: nothing was moved")
        real[key], dests[n] = n, dst
    src = {n: os.path.join(tmp, n) for n in names}
    old = {n: os.path.join(tmp, ".old", n) for n in names}
    stages, moved, saved, n = [], [], [], None
    try:
        os.makedirs(os.path.join(tmp, ".old"), exist_ok=True)
        for n in names:     # written through a link into another folder: first beside its target (one file system)
            if not os.path.samefile(os.path.dirname(dests[n]), out_dir):
                stages.append(make_temp_dir(os.path.dirname(dests[n])))
                shutil.move(src[n], os.path.join(stages[-1], "new"))
                src[n], old[n] = os.path.join(stages[-1], "new"), os.path.join(stages[-1], "old")
        for n in names:
            if os.path.lexists(dests[n]):
                os.replace(dests[n], old[n])
                saved.append(n)
            os.replace(src[n], dests[n])
            moved.append(n)
    except BaseException as exc:
        for m in moved:
            try:
                os.replace(dests[m], src[m])
            except OSError:
                pass
        for m in saved:
            try:
                os.replace(old[m], dests[m])
            except OSError:
                pass
        if isinstance(exc, OSError):
            raise _named_error(exc, out_dir if n is None else dests[n]) from exc
        raise
    finally:
        for stage in stages:        # the earlier file of a link's target (or, after a failure, the new one)
            shutil.rmtree(stage, ignore_errors=True)


def write_together(outputs):
    """Write text files in any folders all together or not at all (``commit_set`` does it for one folder).

    Every text goes to a temporary folder beside its file first; then each file is moved into place, the one it
    replaces kept aside; if a write or a move fails, the files already moved are taken back, the earlier ones
    restored and the folders this call created removed, then the error is raised (``design --out --report``). A
    path that is a symbolic link is written through to the file it points to (:func:`write_target`).

    Parameters
    ----------
    outputs : sequence of (str, str)
        ``(path, text)`` pairs.

    Raises
    ------
    OSError
        The first failed write or move (after rolling back), naming its file (:func:`_named_error`).
    """
    made, staged, moved, path = [], [], [], None
    outputs = [(write_target(os.path.abspath(os.fspath(path))), text) for path, text in outputs]   # before any write
    try:
        for path, text in outputs:
            folder = os.path.dirname(path)
            missing, f = [], folder
            while not os.path.lexists(f):
                missing.append(f)
                f = os.path.dirname(f)
            try:
                os.makedirs(folder, exist_ok=True)
            finally:
                made += [m for m in missing if os.path.isdir(m)]
            tmp = make_temp_dir(folder, "tmp")  # swept if this process dies
            staged.append((path, tmp))
            write_atomic(os.path.join(tmp, "new"), text)
        for path, tmp in staged:
            had_old = os.path.lexists(path)
            if had_old:
                os.replace(path, os.path.join(tmp, "old"))
            moved.append((path, tmp, had_old))
            os.replace(os.path.join(tmp, "new"), path)
    except BaseException as exc:
        failed = path
        for path, tmp, had_old in reversed(moved):
            try:
                if os.path.lexists(os.path.join(tmp, "new")):
                    pass                                    # its move failed: the earlier file is in tmp/old
                else:
                    os.replace(path, os.path.join(tmp, "new"))
                if had_old:
                    os.replace(os.path.join(tmp, "old"), path)
            except OSError:
                pass
        for path, tmp in staged:
            shutil.rmtree(tmp, ignore_errors=True)
        for m in sorted(made, key=len, reverse=True):        # deepest first; only if empty
            try:
                os.rmdir(m)
            except OSError:
                pass
        if isinstance(exc, OSError) and failed is not None:
            raise _named_error(exc, failed) from exc
        raise
    for path, tmp in staged:
        shutil.rmtree(tmp, ignore_errors=True)
