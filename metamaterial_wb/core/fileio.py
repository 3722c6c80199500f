"""Small file helpers: atomic writes so that nothing is ever written half-way."""
import json
import os
import tempfile


def write_atomic(path, data, mode="w"):
    """Write ``data`` (str or bytes) to ``path`` through a temporary file and a rename."""
    path = os.fspath(path)
    folder = os.path.dirname(os.path.abspath(path))
    os.makedirs(folder, exist_ok=True)
    fd, tmp = tempfile.mkstemp(dir=folder, prefix=".tmp-", suffix=os.path.basename(path))
    try:
        with os.fdopen(fd, mode) as f:
            f.write(data)
        umask = os.umask(0)
        os.umask(umask)
        os.chmod(tmp, 0o666 & ~umask)  # mkstemp creates 0600; give the file normal permissions
        os.replace(tmp, path)
    except BaseException:
        if os.path.exists(tmp):
            os.unlink(tmp)
        raise


def write_json(path, obj, indent=1):
    """Serialise ``obj`` completely first, then write it atomically."""
    text = json.dumps(obj, indent=indent, allow_nan=False) + "\n"
    write_atomic(path, text)
