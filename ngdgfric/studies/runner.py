"""Run many independent study cases through dask.distributed, with a cache on disk.

A case is a dict of plain parameters; a case function (importable by the workers, e.g. from
:mod:`ngdgfric.studies.cases`) maps it to a dict of results.  Every finished case is written at once to
``<cache>/<key>.json`` (key: hash of the function's name and the case), so a restarted study
never recomputes it, whatever executor ran it.  ``scheduler``: address of a running dask
scheduler (``tcp://host:8786``) to use its cluster; default: a ``LocalCluster`` with one
single-threaded worker process per core (NGSolve solves are not thread-safe across cases).
"""

import hashlib
import json
import os
import time
from pathlib import Path

from ..progress import log, reporter
from ..threads import call_limited

__all__ = ["case_key", "run_cases"]


def case_key(function, case):
    """Stable cache key of ``function`` applied to ``case``."""
    text = json.dumps([function.__module__, function.__qualname__, case], sort_keys=True, default=str)
    return hashlib.sha1(text.encode()).hexdigest()[:20]


def _client(scheduler, workers):
    from distributed import Client, LocalCluster

    if scheduler is not None:
        return Client(scheduler), None
    cluster = LocalCluster(n_workers=workers or os.cpu_count() or 1, threads_per_worker=1, processes=True,
                           dashboard_address=None)
    return Client(cluster), cluster


def run_cases(function, cases, cache=None, scheduler=None, workers=None, progress=log):
    """Results of ``function(case)`` for every case, in the order of ``cases``.

    ``cache``: folder of finished cases (None: no cache); ``workers``: number of local worker
    processes (default: the machine's cores; ignored with ``scheduler``).  ``progress``: callable(str)
    receiving one line per finished case (default :func:`ngdgfric.progress.log`: the logger "ngdgfric" at INFO,
    silent unless logging is configured; None: no lines).
    """
    if workers is not None and workers < 1:
        raise ValueError(f"workers must be >= 1, got {workers!r}")
    cache = None if cache is None else Path(cache)
    results, todo = {}, []
    for index, case in enumerate(cases):
        path = None if cache is None else cache / f"{case_key(function, case)}.json"
        if path is not None and path.exists():
            results[index] = json.loads(path.read_text())
        else:
            todo.append((index, case, path))
    if todo:
        from distributed import as_completed

        if cache is not None:
            cache.mkdir(parents=True, exist_ok=True)
        client, cluster = _client(scheduler, workers)
        start = time.perf_counter()
        try:
            futures = {client.submit(call_limited, function, case, pure=False): (index, case, path)
                       for index, case, path in todo}
            for done, future in enumerate(as_completed(futures), 1):
                index, case, path = futures[future]
                results[index] = future.result()
                if path is not None:
                    temporary = path.with_suffix(".tmp")
                    temporary.write_text(json.dumps(results[index]))
                    temporary.replace(path)
                reporter(progress)(f"  [{done}/{len(todo)}, {time.perf_counter() - start:.0f} s] {case}")
        finally:
            client.close()
            if cluster is not None:
                cluster.close()
    return [results[index] for index in range(len(cases))]
