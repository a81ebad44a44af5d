# SPDX-License-Identifier: Apache-2.0
"""Writing generated files without disturbing incremental builds."""

import os


def write_if_changed(path: str, text: str) -> bool:
    """Write ``text`` (ASCII/UTF-8, ``\\n`` line ends) to ``path`` unless it
    already holds exactly that; return True when the file was written.

    An unchanged file keeps its modification time, so make/ninja rebuild
    nothing. A changed file is replaced atomically (write beside, rename),
    so a build interrupted half-way never sees half a file. Raises OSError.
    """
    data = text.encode("utf-8")
    try:
        with open(path, "rb") as f:
            if f.read() == data:
                return False
    except FileNotFoundError:
        pass
    tmp = f"{path}.tmp{os.getpid()}"
    try:
        with open(tmp, "wb") as f:
            f.write(data)
        os.replace(tmp, path)
    except OSError:
        try:
            os.unlink(tmp)
        except OSError:
            pass
        raise
    return True
