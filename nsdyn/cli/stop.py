"""How a command stops on SIGINT (Ctrl-C) and SIGTERM: the handler the command line installs.

The first signal raises KeyboardInterrupt, which the command turns into its interrupt line
(:mod:`nsdyn.cli.app`); a later one, while that stop is under way, is ignored. A signal that
arrives while LLVM calls back into Python (numba compiling a kernel) is sent again a moment
later: raised inside the callback it could not stop the compilation and was printed as an
ignored exception with its traceback.
"""

from __future__ import annotations

SIGNALLED = [False]  # set by the handler: an error after a signal is the signal's doing


def on_signal(signum, frame):
    """SIGINT and SIGTERM: note that the command was stopped, then stop it. A later signal,
    while the first one's stop is under way (`timeout` signals the process, then its group),
    is ignored: raised there it cut the stop short (a traceback, a checkpoint folder lost)."""
    if SIGNALLED[0]:
        return
    if _in_llvm_callback(frame):  # raised in LLVM's callback into Python (numba compiling),
        import os  # the interrupt was printed as an ignored exception, with its traceback:
        import threading  # sent again a moment later, when the callback has returned

        threading.Timer(0.05, os.kill, (os.getpid(), signum)).start()
        return
    SIGNALLED[0] = True
    raise KeyboardInterrupt


def _in_llvm_callback(frame) -> bool:
    """Whether ``frame`` or a caller of it runs llvmlite's Python code (its object-cache
    callbacks are called from C: an exception there cannot stop the compilation)."""
    while frame is not None:
        if "llvmlite" in frame.f_code.co_filename:
            return True
        frame = frame.f_back
    return False
