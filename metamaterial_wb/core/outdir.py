"""Output folders (moved out of :mod:`metamaterial_wb.core.fileio`, which re-exports these names).

* :func:`make_dirs` creates an output folder and says which folders it created (:func:`missing_dirs`);
  :func:`remove_new_dirs` removes those again, when still empty, after a failed or interrupted run: a run leaves no
  empty folder behind, and never removes a folder that existed before or anything it did not write.
* :func:`check_scene_not_output` refuses an input file that is one of the run's outputs;
  :func:`earlier_outputs` / :func:`remove_outputs` take away an earlier run's files that a new run does not write.
"""
import json
import os
import shutil

from metamaterial_wb.core.errors import SceneError
from metamaterial_wb.core.inputfile import os_reason


def _same_file(path, other):
    """``path`` and ``other`` are one file (also through a link or another letter case); False when either is not
    there yet, or ``other`` is None or not a path."""
    try:
        return other is not None and os.path.samefile(path, other)
    except (OSError, ValueError, TypeError):
        return False


# ----------------------------------------------------------------------------------------------
# folders a run creates
# ----------------------------------------------------------------------------------------------
def missing_dirs(path):
    """The folders of ``path`` (itself and its parents) that do not exist yet, innermost first.

    Parameters
    ----------
    path : str or os.PathLike

    Returns
    -------
    list of str
        Absolute paths.
    """
    out = []
    path = os.path.abspath(os.fspath(path))
    while not os.path.lexists(path):
        out.append(path)
        parent = os.path.dirname(path)
        if parent == path:
            break
        path = parent
    return out


def remove_new_dirs(made):
    """Remove the folders ``made`` (:func:`missing_dirs`, innermost first) that are still empty: the folders a failed
    run created. The first that cannot be removed (not empty: it holds what others put there) ends it, as its parents
    hold it.

    Parameters
    ----------
    made : sequence of str
    """
    for d in made:
        try:
            os.rmdir(d)
        except FileNotFoundError:
            continue
        except OSError:
            break


def make_dirs(folder, option="--out"):
    """Create ``folder`` and its missing parents.

    Parameters
    ----------
    folder : str
    option : str, optional
        The option the error names.

    Returns
    -------
    list of str
        The folders this call created, innermost first (for :func:`remove_new_dirs` when the run fails).

    Raises
    ------
    SceneError
        The folder cannot be created (naming it and the reason; what was created is removed again).
    """
    made = missing_dirs(folder)
    try:
        os.makedirs(folder, exist_ok=True)
    except BaseException as exc:
        remove_new_dirs(made)
        if isinstance(exc, OSError):
            raise SceneError(option, f"cannot create folder {folder}: {os_reason(exc)}") from None
        raise
    return made


# ----------------------------------------------------------------------------------------------
# the outputs in a folder
# ----------------------------------------------------------------------------------------------
def check_scene_not_output(out_dir, names, scene, option="--out", writer="the run", what_input="the scene"):
    """Refuse, before any work, an output ``out_dir/NAME`` that is the input file ``scene`` (the same file, also
    through a link or another letter case): the run would overwrite or remove what it reads (``DIR/manifest.json``
    given to ``build --out DIR``, ``DIR/summary.json`` to ``simulate --out DIR``).

    Parameters
    ----------
    out_dir : str
        The output folder.
    names : sequence
        The outputs' names in it: plain names, or ``(name, field, what)`` triples (``what``: the output's words).
    scene : str
        The input file.
    option : str, optional
        The option the error names.
    writer : str, optional
        Who writes the outputs, for the message ("the build").
    what_input : str, optional
        What the input file is, for the message ("the scene", "the sleeve spec").

    Raises
    ------
    SceneError
        One of the outputs is ``scene``.
    """
    for item in names:
        n, what = (item, item) if isinstance(item, str) else (item[0], item[2])
        path = os.path.join(out_dir, n)
        if _same_file(path, scene):
            where = "" if os.path.abspath(scene) == os.path.abspath(path) else f" ({scene})"
            raise SceneError(option, f"{path} is {what_input} this command reads{where}; {writer} writes {what} "
                                     f"there and it would be overwritten: choose another output folder or move "
                                     f"{what_input}")


def earlier_outputs(out_dir, listing, fmt, names, key="files"):
    """The outputs an earlier run listed in ``out_dir/listing`` (a JSON file of format ``fmt`` with the list
    ``key``) that the new set ``names`` does not write: left in place they would sit beside a listing that no
    longer names them. Only plain names that the earlier listing holds and that exist now; anything else in the
    folder is the user's and is never touched. Take them before the new set is moved in.

    Parameters
    ----------
    out_dir : str
        The output folder.
    listing : str
        The earlier run's listing in it (``manifest.json``, ``summary.json``).
    fmt : str
        The listing's ``"format"``; another format (or none) lists nothing.
    names : sequence of str
        What the new run writes.
    key : str, optional
        The listing's key of the file names.

    Returns
    -------
    list of str
        Sorted names to remove once the new set is in place.
    """
    try:
        with open(os.path.join(out_dir, listing), encoding="utf-8") as f:
            old = json.load(f)
    except (OSError, ValueError):
        return []
    if not isinstance(old, dict) or old.get("format") != fmt or not isinstance(old.get(key), list):
        return []
    keep = set(names)
    return sorted({n for n in old[key] if isinstance(n, str) and n not in keep and n == os.path.basename(n)
                   and n not in ("", ".", "..") and os.path.lexists(os.path.join(out_dir, n))
                   and not os.path.islink(os.path.join(out_dir, n))})


def remove_outputs(out_dir, stale):
    """Remove ``stale`` (from :func:`earlier_outputs`; a folder with its contents).

    Parameters
    ----------
    out_dir : str
        The output folder.
    stale : sequence of str
        Names inside it.

    Returns
    -------
    list of str
        The names removed (one that cannot be removed is skipped).
    """
    gone = []
    for n in stale:
        p = os.path.join(out_dir, n)
        try:
            if os.path.isdir(p):
                shutil.rmtree(p)
            else:
                os.remove(p)
            gone.append(n)
        except OSError:
            pass
    return gone
