"""Bounded reads of input files: regular files only, at most a given size, never blocking.

A path can name anything: a FIFO (whose ``open`` waits for a writer), a
device (``/dev/zero`` never ends), a file still growing.  :func:`read_bounded`
opens without blocking, refuses anything but a regular file, and reads at most
one byte past its limit, so that no input can stall a command or fill memory.
"""

from __future__ import annotations

import errno
import os
import stat

__all__ = ["read_bounded"]


def read_bounded(path, limit: int) -> bytes:
    """The bytes of the regular file ``path``, if it has at most ``limit`` of them.

    Raises
    ------
    OSError
        The file cannot be opened, is not a regular file (a FIFO, a device, a
        directory) or has more than ``limit`` bytes; ``strerror`` says which.

    Examples
    --------
    >>> read_bounded("/dev/zero", 10)
    Traceback (most recent call last):
    ...
    OSError: [Errno 22] not a regular file (a device, a FIFO or a directory): '/dev/zero'
    """
    flags = os.O_RDONLY | getattr(os, "O_NONBLOCK", 0) | getattr(os, "O_CLOEXEC", 0)
    fd = os.open(path, flags)       # non-blocking: opening a FIFO does not wait for a writer
    try:
        if not stat.S_ISREG(os.fstat(fd).st_mode):
            raise OSError(errno.EINVAL, "not a regular file (a device, a FIFO or a directory)",
                          os.fspath(path))
        chunks, size = [], 0
        while size <= limit:
            chunk = os.read(fd, min(1 << 20, limit + 1 - size))
            if not chunk:
                break
            chunks.append(chunk)
            size += len(chunk)
        if size > limit:
            raise OSError(errno.EFBIG, f"file larger than {limit} bytes", os.fspath(path))
        return b"".join(chunks)
    finally:
        os.close(fd)
