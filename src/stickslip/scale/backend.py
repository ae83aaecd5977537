"""Run a job's blocks in process or on a Dask distributed cluster, into a store or into memory.

A *job* is anything with a ``task(block)`` method that returns a picklable
callable computing that block's arrays (a mapping from variable name to an
array of the block's shape). The blocks run

- in process, one after the other (each one parallel inside, on numba's threads),
  when neither ``scheduler`` nor ``workers`` is given: no Dask is imported;
- on an existing Dask cluster (``scheduler``: its address, or a
  ``distributed.Client``);
- on a ``LocalCluster`` of ``workers`` processes started for the run, one task
  at a time per worker, numba's threads shared out among them.

With a store, each block is written where it was computed (workers write their
own blocks: the store must be on a file system they all see) and only the
blocks not yet in the store run. Without one, the arrays come back to the
caller. At most a few blocks per worker are in flight, so memory stays bounded
however many blocks there are.

A job may also have ``worker_cleanup()``, returning a picklable callable (or None)
that an existing cluster's workers run once the job's blocks are done: what a
worker keeps between a job's blocks (a GPU's buffers) is not kept after it. A
``LocalCluster`` started for the run ends with it, and its processes' memory with them.
"""

from __future__ import annotations

import contextlib
import logging
import os
import time
from collections.abc import Callable, Iterator, Mapping
from concurrent.futures import CancelledError
from dataclasses import dataclass
from typing import Any

import numpy as np
import numpy.typing as npt

from .progress import Progress, ProgressLike
from .store import Block, ChunkStore, Layout

__all__ = ["RunReport", "check_scheduler", "local_cluster", "local_threads", "run_blocks", "run_job"]

Arrays = Mapping[str, npt.NDArray[Any]]


@dataclass(frozen=True)
class RunReport:
    """What a run did.

    Attributes
    ----------
    blocks : int
        Blocks of the job.
    reused : int
        Blocks found finished in the store (verified), not computed again.
    computed : int
        Blocks computed by this run.
    points : int
        Grid points computed by this run.
    seconds : float
        Wall time of the run.
    backend : str
        ``in-process``, ``local-cluster (N workers)`` or the scheduler's address.

    """

    blocks: int
    reused: int
    computed: int
    points: int
    seconds: float
    backend: str

    def as_dict(self) -> dict[str, Any]:
        """Return the report as plain numbers (``--json``)."""
        return dict(self.__dict__)

    def to_json(self) -> str:
        """Return the report as JSON (the ``run`` attribute of a result read from its store)."""
        import json

        return json.dumps(self.as_dict())


def local_cluster(workers: int, numba_threads: int | None = None, *, log_level: int = logging.ERROR) -> Any:
    """Start a ``distributed.LocalCluster`` as stickslip runs on one: worker processes of one task each.

    Parameters
    ----------
    workers : int
        Worker processes.
    numba_threads : int, optional
        ``NUMBA_NUM_THREADS`` of each worker; default the cores shared out
        (:func:`local_threads`).
    log_level : int, optional
        Level below which the cluster's log messages are silenced.

    """
    from distributed import LocalCluster

    threads = local_threads(workers) if numba_threads is None else numba_threads
    return LocalCluster(
        n_workers=workers,
        threads_per_worker=1,
        processes=True,
        dashboard_address=None,
        silence_logs=log_level,
        env={"NUMBA_NUM_THREADS": str(threads)},
    )


def local_threads(workers: int) -> int:
    """Numba threads for each of ``workers`` processes on this machine (cores shared out)."""
    cores = os.cpu_count() or 1
    return max(1, cores // max(1, workers))


def check_scheduler(scheduler: Any) -> None:
    """Refuse a scheduler that is neither a ``distributed.Client`` nor a well-formed address.

    Before anything is made (a store) or waited for (the 30 s of a connection): Dask
    itself waits 30 s in silence on a port outside 1..65535, and says of ``nonsense``
    only "missing port number in address", without naming the argument.

    Raises
    ------
    ValueError
        Naming ``scheduler`` and what was expected.

    """
    if scheduler is None or not isinstance(scheduler, str):
        return  # a Client (checked where it is used), or none
    from distributed.comm.addressing import parse_address, parse_host_port

    expected = "expected a Dask scheduler's address such as tcp://10.0.0.1:8786"
    try:
        scheme, loc = parse_address(scheduler, strict=False)
        port = parse_host_port(loc)[1] if scheme in ("tcp", "tls") else 1
    except (TypeError, ValueError) as exc:
        raise ValueError(f"scheduler={scheduler!r}: {expected} ({exc})") from None
    if not 1 <= int(port) <= 65535:
        raise ValueError(f"scheduler={scheduler!r}: port {port} is not a port (1 to 65535); {expected}")


def run_blocks(
    job: Any,
    layout: Layout,
    *,
    store: ChunkStore | None = None,
    scheduler: Any = None,
    workers: int | None = None,
    progress: ProgressLike = None,
    desc: str = "",
) -> tuple[dict[str, npt.NDArray[Any]] | None, RunReport]:
    """Compute every block of ``job`` not already in ``store``.

    Parameters
    ----------
    job : object
        Has ``task(block) -> callable`` (the callable returns the block's arrays).
    layout : Layout
        The result's shape and blocks (the store's, when there is one).
    store : ChunkStore, optional
        Write each block there as it finishes; skip the blocks already there.
    scheduler : str or distributed.Client, optional
        Run on this Dask cluster.
    workers : int, optional
        Start a LocalCluster of this many worker processes for the run.
    progress : bool, callable or None
        Progress bar (see :class:`~.progress.Progress`).
    desc : str
        Label of the progress bar.

    Returns
    -------
    arrays : dict or None
        Without a store, the full arrays of every variable; with one, None.
    report : RunReport

    """
    t0 = time.perf_counter()
    if workers is not None and (isinstance(workers, bool) or not isinstance(workers, int) or workers < 1):
        raise ValueError(f"workers={workers!r}: expected a whole number of worker processes >= 1")
    most = 4 * (os.cpu_count() or 1)
    if workers is not None and workers > most:  # a process each, started on this machine
        raise ValueError(
            f"workers={workers}: expected at most {most} local worker processes (4 per core of this "
            "machine); a larger cluster is a Dask scheduler's (scheduler=)"
        )
    if scheduler is not None and workers is not None:
        raise ValueError("give either scheduler (an existing cluster) or workers (a local one), not both")
    check_scheduler(scheduler)
    done = store.finished() if store is not None else set()
    todo = [b for b in layout.blocks() if b.index not in done]
    arrays = None if store is not None else _allocate(layout)
    bar = Progress(
        total_points=sum(b.points for b in todo),
        total_blocks=len(todo),
        progress=progress,
        desc=desc or layout.kind,
    )

    def finish(block: Block, result: Arrays | None) -> None:
        if arrays is not None and result is not None:
            for v in layout.variables:
                arrays[v.name][layout.region(v.name, block)] = result[v.name]
        bar.update(block.points)

    try:
        if scheduler is None and workers is None:
            backend = "in-process"
            for block in todo:
                result = job.task(block)()
                if store is not None:
                    store.write_block(block, result)
                    result = None
                finish(block, result)
        else:
            backend = _run_dask(job, layout, todo, store, scheduler, workers, finish)
    finally:
        bar.close()
    report = RunReport(
        blocks=layout.n_blocks,
        reused=len(done),
        computed=len(todo),
        points=sum(b.points for b in todo),
        seconds=time.perf_counter() - t0,
        backend=backend,
    )
    return arrays, report


def _allocate(layout: Layout) -> dict[str, npt.NDArray[Any]]:
    out = {}
    for v in layout.variables:
        shape = layout.shape[: len(v.dims)]
        out[v.name] = np.full(shape, v.fill, dtype=v.dtype)
    return out


def _block_task(
    task: Callable[[], Arrays], block: Block, store: ChunkStore | None
) -> tuple[int, Arrays | None]:
    """Run on a worker: compute one block and write it (with a store) or send it back."""
    result = task()
    if store is not None:
        store.write_block(block, result)
        return block.index, None
    return block.index, result


#: seconds a job waits on a cluster without workers before it stops (and says so)
NO_WORKERS_TIMEOUT = 120.0


def _completed(ac: Any, client: Any, backend: str) -> Any:
    """Yield the futures of ``ac`` as they finish.

    Stop with an error when the cluster has had no worker for :data:`NO_WORKERS_TIMEOUT`
    seconds: a job on a scheduler without workers, or whose workers all died, would otherwise
    wait without a word until it is killed.
    """
    idle_since: float | None = None
    checked = 0.0
    while not ac.is_empty():
        if ac.has_ready():
            idle_since = None
            yield from ac.next_batch(block=False)
            continue
        now = time.monotonic()
        if now - checked >= 2.0:
            checked = now
            if client.nthreads():
                idle_since = None
            elif idle_since is None:
                idle_since = now
            elif now - idle_since > NO_WORKERS_TIMEOUT:
                raise RuntimeError(
                    f"the Dask cluster ({backend}) has had no workers for {NO_WORKERS_TIMEOUT:g} s: "
                    "start some (dask worker ADDRESS) and run the same command again"
                )
        time.sleep(0.02)


#: how long a job waits for a scheduler's address to answer
CONNECT_TIMEOUT = "30s"


@contextlib.contextmanager
def _client_log_quiet() -> Iterator[None]:
    """Silence Dask's client log (below CRITICAL) over a block: a lost cluster's tracebacks."""
    client_log = logging.getLogger("distributed.client")
    level = client_log.level
    client_log.setLevel(logging.CRITICAL)
    try:
        yield
    finally:
        client_log.setLevel(level)


def _connect(scheduler: str) -> Any:
    """Return a ``distributed.Client`` of the scheduler at this address (:data:`CONNECT_TIMEOUT`).

    Raises
    ------
    ValueError
        Where no scheduler answers there, naming ``scheduler`` and why.

    """
    from distributed import Client

    try:
        return Client(str(scheduler), timeout=CONNECT_TIMEOUT)
    except (OSError, TimeoutError, TypeError, ValueError, ImportError) as exc:  # ucx:// without ucx
        raise ValueError(f"scheduler={scheduler!r}: cannot reach a Dask scheduler there ({exc})") from None


def _run_dask(
    job: Any,
    layout: Layout,
    todo: list[Block],
    store: ChunkStore | None,
    scheduler: Any,
    workers: int | None,
    finish: Callable[[Block, Arrays | None], None],
) -> str:
    from distributed import Client, as_completed

    cluster = None
    own_client = False
    if workers is not None:
        cluster = local_cluster(workers)
        client = Client(cluster)
        own_client = True
        backend = f"local-cluster ({workers} workers)"
    elif isinstance(scheduler, Client):
        client = scheduler
        backend = f"dask {scheduler.scheduler.address}" if scheduler.scheduler else "dask"
    else:
        client = _connect(scheduler)
        own_client = True
        backend = f"dask {scheduler}"
    # the client logs a lost connection with tracebacks at ERROR (also while it closes); the
    # RuntimeError below says it in one line
    with _client_log_quiet():
        try:
            threads = sum(client.nthreads().values()) or 1
            in_flight = 2 * threads + 2
            by_index = {b.index: b for b in todo}
            pending = iter(todo)
            ac = as_completed()
            token = f"{layout.kind}-{os.getpid()}-{time.monotonic_ns()}"

            def submit(block: Block) -> None:
                ac.add(
                    client.submit(
                        _block_task,
                        job.task(block),
                        block,
                        store,
                        key=f"stickslip-{token}-{block.index}",
                        pure=False,
                    )
                )

            for block in pending:
                submit(block)
                if ac.count() >= in_flight:
                    break
            try:
                for fut in _completed(ac, client, backend):
                    index, result = fut.result()
                    fut.release()
                    finish(by_index[index], result)
                    nxt = next(pending, None)
                    if nxt is not None:
                        submit(nxt)
            except (CancelledError, OSError, TimeoutError) as exc:  # the cluster, not the job
                kept = "the blocks finished are kept in the store" if store is not None else "nothing is kept"
                why = (str(exc).strip().splitlines() or [""])[0]
                raise RuntimeError(
                    f"the Dask cluster ({backend}) was lost mid-job ({type(exc).__name__}: {why}); {kept}: "
                    "run the same command again (with --store, only the missing blocks are computed)"
                ) from None
        finally:
            if cluster is None:
                _clean_workers(job, client)
            if own_client:
                client.close()
            if cluster is not None:
                cluster.close()
    return backend


def _clean_workers(job: Any, client: Any) -> None:
    """Send the job's ``worker_cleanup()`` to every worker of an existing cluster (best effort).

    Sent, not waited for (a worker whose event loop is held by another job's task runs
    it later), and not sent to a cluster lost mid-job: what is released is a worker's
    memory, not the job's result.
    """
    cleanup = getattr(job, "worker_cleanup", None)
    fn = cleanup() if cleanup is not None else None
    if fn is None or getattr(client, "status", None) != "running":  # a lost one: its reconnect waits 30 s
        return
    with contextlib.suppress(Exception):  # a worker gone: nothing to release there
        # sent, not waited for: a worker busy elsewhere runs it when it can (distributed runs a
        # function without waiting only as a coroutine)
        client.run(_cleanup_coroutine, fn, wait=False)


async def _cleanup_coroutine(fn: Callable[[], Any]) -> None:
    """Run a job's clean-up on a worker (the coroutine that ``client.run(..., wait=False)`` needs)."""
    fn()


def run_job(
    job: Any,
    layout: Layout,
    *,
    store: str | os.PathLike[str] | None,
    scheduler: Any,
    workers: int | None,
    progress: ProgressLike,
    desc: str,
    load: bool = True,
) -> Any:
    """Run a job (in process or on Dask, into its store or into memory); return its Dataset.

    Without a store: ``job.dataset(arrays)``. With one: the store read back
    (loaded when ``load``, lazily otherwise), with the run's :class:`RunReport`
    as JSON in its ``run`` attribute.
    """
    check_scheduler(scheduler)  # before the store is made
    # an address is reached before the store is made, too: an unreachable one must not leave
    # an empty store behind; the client is then this job's to close
    client = _connect(scheduler) if isinstance(scheduler, str) and store is not None else None
    try:
        chunks = ChunkStore.open(store, layout) if store is not None else None
        arrays, report = run_blocks(
            job,
            chunks.layout if chunks is not None else layout,
            store=chunks,
            scheduler=client if client is not None else scheduler,
            workers=workers,
            progress=progress,
            desc=desc,
        )
    finally:
        if client is not None:
            with _client_log_quiet():  # a lost cluster's close logs tracebacks
                client.close()
    if chunks is None:
        assert arrays is not None
        return job.dataset(arrays)
    ds = chunks.open_dataset()
    if load:
        ds = ds.load()
    ds.attrs["run"] = report.to_json()
    return ds
