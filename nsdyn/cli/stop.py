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
        import threading  # the interrupt was printed as an ignored exception, with its

        resend = threading.Timer(0.05, _resend, (signum,))  # traceback: sent again a moment
        resend.daemon = True  # later, when the callback has returned
        resend.start()
        return
    SIGNALLED[0] = True
    raise KeyboardInterrupt


def _resend(signum: int) -> None:
    """Send ``signum`` to this process again while this handler still handles it (a command
    that ended meanwhile, its handlers restored in a caller's process: not sent)."""
    import os
    import signal

    if signal.getsignal(signum) is on_signal and not SIGNALLED[0]:
        os.kill(os.getpid(), signum)


def _in_llvm_callback(frame) -> bool:
    """Whether ``frame`` or a caller of it runs llvmlite's Python code (its object-cache
    callbacks are called from C: an exception there cannot stop the compilation)."""
    while frame is not None:
        if "llvmlite" in frame.f_code.co_filename:
            return True
        frame = frame.f_back
    return False
