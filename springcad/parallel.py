"""Run one step of a build in a second process while this one does another.

:func:`beside` forks a child that runs ``func(*args, progress=..., **kwargs)`` while the
caller goes on (the FEA outputs' renders beside the part exports: the two use the two
cores). The child inherits the caller's memory (fork: the verification and the solids
are not copied or pickled), writes its files, and sends back its result and its
progress messages, which the caller replays in order when it collects the result, so
the console never shows two steps' lines interleaved.

Clean on every way out: an exception in the child is raised again in the caller; when
the caller leaves the block early (an error, Ctrl-C, SIGTERM) the child is terminated
and reaped before the caller's temporary folder is removed; a child whose parent dies
(SIGKILL) is sent SIGTERM by the kernel (Linux ``PR_SET_PDEATHSIG``), so no orphan
writes on. Where fork is not available, or parallel steps are off
(:data:`springcad.options.PARALLEL` or ``$SPRINGCAD_PARALLEL=0``), the step runs in the
caller, before the block.
"""

from __future__ import annotations

import contextlib
import gc
import importlib
import os
import signal
import sys
import traceback

from springcad.options import PARALLEL
from springcad.progress import ambient, no_progress, reporting

ENV_SWITCH = "SPRINGCAD_PARALLEL"
#: the signals that stop a build (Ctrl-C, SIGTERM)
_STOP_SIGNALS = {signal.SIGINT, signal.SIGTERM}
_OFF = ("0", "off", "no", "false")


def enabled() -> bool:
    """Whether steps may run in a second process (fork available, not switched off, and
    this process no daemonic child, which multiprocessing allows no children of its own: a
    step that forks, run in another's child or a process pool's worker, runs serially)."""
    import multiprocessing

    return (PARALLEL and os.environ.get(ENV_SWITCH, "").strip().lower() not in _OFF
            and "fork" in multiprocessing.get_all_start_methods()
            and not multiprocessing.current_process().daemon)  # a daemon has no children


def trim_heap() -> None:
    """Give the heap memory freed by earlier steps back to the OS (glibc ``malloc_trim``;
    nothing elsewhere): the FEA's factorisations leave hundreds of MB of free heap that the
    process would otherwise keep, and a forked child would start from."""
    with contextlib.suppress(Exception):
        import ctypes

        ctypes.CDLL("libc.so.6").malloc_trim(0)


@contextlib.contextmanager
def single_threaded_blas():
    """Run the block with one BLAS thread (``threadpoolctl``; unchanged without it).

    For work made of many small dense products and solves (the contact sweep's Newton
    iterations on a ~1400-DOF sector): a multi-threaded BLAS gains nothing there, and on a
    busy 2-core machine its spinning threads made the paper S1 contact sweep 3x slower
    (measured: 9.6 s CPU with OpenBLAS's threads, 3.2 s with one); and the fits, which
    factor tall, thin Jacobians (thousands x a few), several times slower."""
    try:
        from threadpoolctl import threadpool_limits
    except ImportError:  # optional: only a speed-up
        yield
        return
    with threadpool_limits(limits=1, user_api="blas"):
        yield


@contextlib.contextmanager
def single_threaded():
    """Run the block with one thread in every native pool (BLAS and OpenMP:
    ``threadpoolctl``; unchanged without it), as a second process runs (:func:`_child`):
    work that may run in either place gives the same numbers in both."""
    try:
        from threadpoolctl import threadpool_limits
    except ImportError:  # optional: only a speed-up
        yield
        return
    with threadpool_limits(limits=1):
        yield


#: glibc mallopt parameters (malloc.h) and the size above which a block is its own mapping
_M_TRIM_THRESHOLD, _M_MMAP_THRESHOLD = -1, -3
RETURN_ABOVE_BYTES = 4 * 2 ** 20


def return_freed_memory() -> None:
    """Make glibc give large freed blocks back to the OS at once (``mallopt``; nothing
    elsewhere). Its default raises the mapping threshold to the largest block freed so far
    (up to 32 MB), so after the FEA's arrays every later array comes from the heap, which
    only shrinks from its top: the build's CAD steps ran on a heap of freed FEA pages.
    Fixed at 4 MiB (measured on the default build, cold, load 12: largest process 1041 ->
    995 MB, CPU 29.1 -> 30.7 s; at 128 KiB the same 994 MB for 33.7 s, the page faults of
    every mid-sized array)."""
    with contextlib.suppress(Exception):
        import ctypes

        libc = ctypes.CDLL("libc.so.6")
        libc.mallopt(_M_MMAP_THRESHOLD, RETURN_ABOVE_BYTES)
        libc.mallopt(_M_TRIM_THRESHOLD, RETURN_ABOVE_BYTES)


#: modules a later step of this process will import, imported by the caller while it waits
#: for a child (:func:`import_while_waiting`)
_WAITING_IMPORTS: list[str] = []


def import_while_waiting(*modules: str) -> None:
    """Name modules a later step of this process imports: the caller imports them, one at a
    time, whenever it would otherwise wait for a child's result (:meth:`Pending.result`)
    that is not ready, instead of leaving its core idle. ``springcad build`` names the CAD
    kernel's modules (build123d and OCP: about 2.5 s of CPU) while the verification waits
    for its 3D factor, which is solved beside it, so the solids no longer start with their
    import. A module that fails to import is left for its step to report."""
    _WAITING_IMPORTS.extend(m for m in modules if m not in _WAITING_IMPORTS)


def _import_while(not_ready) -> None:
    """Import the modules :func:`import_while_waiting` named while ``not_ready()``."""
    while _WAITING_IMPORTS and not_ready():
        name = _WAITING_IMPORTS.pop(0)
        if name not in sys.modules:
            with contextlib.suppress(Exception):
                importlib.import_module(name)


class Pending:
    """The result of a step run beside the caller (:func:`beside`)."""

    def __init__(self, proc=None, conn=None, value=None, progress=None, deferred=None):
        self._proc, self._conn, self._value = proc, conn, value
        self._sharing = proc is not None  # the caller's objects frozen for this child
        self._progress = progress
        self._deferred = deferred  # run in the caller by the first .result()
        self._done = proc is None and deferred is None

    def result(self):
        """The step's return value (waits for the child); its progress is replayed first.

        Raises:
            the child's exception; RuntimeError when the child died without an answer.
        """
        if self._done:
            return self._value
        if self._deferred is not None:
            self._value, self._deferred, self._done = self._deferred(), None, True
            return self._value
        _import_while(lambda: not self._conn.poll())
        try:
            status, payload, messages = self._conn.recv()
        except EOFError:
            self._reap()
            raise RuntimeError(f"the second process of the build ended without a result "
                               f"(exit code {self._proc.exitcode})") from None
        finally:
            self._done = True
        self._reap()
        for message, fraction in messages:
            self._progress(message, fraction)
        if status == "error":
            raise payload
        self._value = payload
        return payload

    def ready(self) -> bool:
        """Whether :meth:`result` would return (or raise) without waiting."""
        return self._done or self._deferred is not None or self._conn.poll()

    def stop(self) -> None:
        """Terminate and reap the child if it still runs (the caller is leaving early)."""
        proc = self._proc
        self._deferred = None
        if proc is None:
            return
        if proc.is_alive():
            proc.terminate()
            proc.join(10)
            if proc.is_alive():
                proc.kill()
        self._reap()
        self._conn.close()

    def _reap(self) -> None:
        """Wait for the child to end; the caller's garbage collector may then scan the
        objects it shared with it again (:func:`_share`)."""
        self._proc.join()
        if self._sharing:
            self._sharing = False
            _unshare()


#: children alive that share the caller's objects (:func:`_share`)
_SHARING = [0]


def _share() -> None:
    """Leave the objects alive now out of this process's garbage collections until every
    child forked from here has ended (``gc.freeze``; :func:`_unshare`). A full collection
    writes into every object it scans, which copies its page out of what the parent shares
    with its children (copy on write): the parent unfrozen at once after the fork (as
    before) copied most of its Python heap while the FEA outputs were written beside the
    solids (the default build: the parent's and the child's pages shared fell to ~90 MB
    of the ~240 MB the child started with). The child inherits the frozen objects, so its
    own collections leave them alone too. Cyclic garbage among them waits for the
    unfreeze."""
    gc.freeze()
    _SHARING[0] += 1


def _unshare() -> None:
    """A child that shared the caller's objects has ended; the last one unfreezes them."""
    _SHARING[0] -= 1
    if _SHARING[0] == 0:
        gc.unfreeze()


def _child(conn, func, args, kwargs) -> None:
    """The child's side: default signal handling, die with the parent, run, send back."""
    signal.signal(signal.SIGINT, signal.SIG_DFL)
    signal.signal(signal.SIGTERM, signal.SIG_DFL)
    signal.pthread_sigmask(signal.SIG_UNBLOCK, _STOP_SIGNALS)  # blocked by _fork until now
    with contextlib.suppress(Exception):
        import ctypes

        ctypes.CDLL(None).prctl(1, signal.SIGTERM)  # PR_SET_PDEATHSIG
    messages = []
    try:
        with single_threaded():  # the parent uses the other core; no forked thread pools
            value = func(*args, progress=lambda m, f=None: messages.append((m, f)), **kwargs)
        conn.send(("ok", value, messages))
    except BaseException as err:  # noqa: BLE001 - every failure goes back to the parent
        try:
            conn.send(("error", err, messages))
        except Exception:  # an exception that does not pickle: its text
            conn.send(("error", RuntimeError("".join(traceback.format_exception(err))),
                       messages))
    finally:
        conn.close()


def _fork(func, args, kwargs, progress) -> Pending:
    """Start ``func`` in a forked child (see :func:`beside`)."""
    import multiprocessing

    trim_heap()
    ctx = multiprocessing.get_context("fork")
    recv, send = ctx.Pipe(duplex=False)
    proc = ctx.Process(target=_child, args=(send, func, args, kwargs), daemon=True)
    # the objects alive at the fork are left out of both processes' garbage collections
    # while the child lives (_share)
    _share()
    # the child starts with SIGINT and SIGTERM blocked, until it has set their default
    # actions (_child): a signal in between would run the handler it inherited from the
    # CLI, which raises in the child and prints a traceback (the parent stopping a child it
    # had just started, on Ctrl-C, did exactly that)
    blocked = signal.pthread_sigmask(signal.SIG_BLOCK, _STOP_SIGNALS)
    try:
        proc.start()
    except BaseException:
        _unshare()
        raise
    finally:
        signal.pthread_sigmask(signal.SIG_SETMASK, blocked)
    send.close()
    return Pending(proc, recv, progress=progress)


@contextlib.contextmanager
def beside(func, *args, progress=None, **kwargs):
    """Run ``func(*args, progress=..., **kwargs)`` in a forked child while the block runs.

    Yields a :class:`Pending`; call ``.result()`` inside the block to wait for the value.
    Leaving the block without it (an exception, an interrupt) terminates the child.
    ``func``'s result and exceptions must pickle. Where steps do not run in a second
    process (:func:`enabled`), ``func`` runs before the block.
    """
    progress = progress or no_progress
    if not enabled():
        yield Pending(value=func(*args, progress=progress, **kwargs))
        return
    pending = _fork(func, args, kwargs, progress)
    try:
        yield pending
    finally:
        pending.stop()


def ahead(stack: contextlib.ExitStack, func, *args, progress=None, **kwargs) -> Pending:
    """Start ``func(*args, progress=..., **kwargs)`` in a forked child whose result may or
    may not be asked for (work done ahead on the other core: a 3D factor that the correction
    loop needs only if its iteration meets the target).

    The child is stopped (terminated if it still runs, its result and progress dropped) by
    ``.stop()`` or when ``stack`` closes. Where steps do not run in a second process
    (:func:`enabled`), ``func`` runs in the caller when ``.result()`` is first called, and
    never when it is not: the same results, in the same order, without the second core.
    """
    progress = progress or no_progress
    if not enabled():
        return Pending(deferred=lambda: func(*args, progress=progress, **kwargs))
    pending = _fork(func, args, kwargs, progress)
    stack.callback(pending.stop)
    return pending


def each_on_two_cores(func, items: list) -> tuple[list, int]:
    """``[func(x) for x in items]``, in order, the second, fourth, ... in a forked child
    (:func:`ahead`) while this process runs the others: for independent pieces of work
    that each take a second or more (a refusal's design probes, its changes checked with
    the whole job). The child's progress lines are replayed after this process's.

    Returns:
        (the results, how many of them the child computed: 0 when steps do not run in a
        second process, or for fewer than two items).
    """
    if len(items) < 2 or not enabled():
        return [func(x) for x in items], 0
    with contextlib.ExitStack() as stack:
        theirs = ahead(stack, _each, func, items[1::2], progress=ambient())
        mine = [func(x) for x in items[0::2]]
        results = [None] * len(items)
        results[0::2], results[1::2] = mine, theirs.result()
    return results, len(items[1::2])


def _each(func, items: list, progress=None) -> list:
    """``[func(x) for x in items]`` with their progress sent to ``progress``."""
    with reporting(progress):
        return [func(x) for x in items]
