"""Run a planned chatter study on a Dask cluster: one task per case, then collect.

    chatter plan main-job --out STUDY [options]
    python studies/chatter/dask/chatter_dask.py STUDY --local 4          # a LocalCluster of 4 processes
    python studies/chatter/dask/chatter_dask.py STUDY --scheduler tcp://host:8786
    python studies/chatter/dask/chatter_dask.py STUDY --slurm 20         # dask-jobqueue SLURMCluster

Each task runs ``chatter run STUDY --case ID --threads 1`` in a subprocess; the result file is
written atomically by chatter, so a task retried after a lost worker (``--retries``) or run twice
gives the same bytes, and cases that already have a result are skipped. After every task has
finished, ``chatter collect STUDY`` writes the tables and figures: byte-identical to a local run.
"""
from __future__ import annotations

import argparse
import json
import os
import shutil
import subprocess
from pathlib import Path


def case_ids(study: str | os.PathLike) -> list[str]:
    """The case IDs of a planned study, in manifest order."""
    with open(Path(study) / "manifest.json", encoding="utf-8") as f:
        manifest = json.load(f)
    return [c["id"] for c in manifest["cases"]]


def run_case(chatter: str, study: str, case_id: str) -> str:
    """One Dask task: run one case (a no-op if its result exists)."""
    r = subprocess.run([chatter, "run", study, "--case", case_id, "--threads", "1"],
                       capture_output=True, text=True)
    if r.returncode != 0:
        raise RuntimeError(f"case {case_id}: {r.stderr.strip() or r.stdout.strip()}")
    return case_id


def run_study(client, chatter: str, study: str, retries: int = 3, on_done=None) -> str:
    """Run every case of ``study`` on ``client`` (a ``dask.distributed.Client``), then collect.

    ``on_done(case_id, n_done)`` is called as cases finish (progress, tests). Returns the output
    of ``chatter collect``; raises ``RuntimeError`` with chatter's message if a case fails after
    its retries.
    """
    from dask.distributed import as_completed

    study = str(Path(study).resolve())
    ids = case_ids(study)
    futures = [client.submit(run_case, chatter, study, i, key=f"chatter-case-{i}", retries=retries, pure=False)
               for i in ids]
    for n, fut in enumerate(as_completed(futures), start=1):
        case_id = fut.result()
        if on_done is not None:
            on_done(case_id, n)
    r = subprocess.run([chatter, "collect", study], capture_output=True, text=True)
    if r.returncode != 0:
        raise RuntimeError(f"collect: {r.stderr.strip()}")
    return r.stdout


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("study", help="the study folder (chatter plan ... --out STUDY)")
    where = p.add_mutually_exclusive_group(required=True)
    where.add_argument("--local", type=int, metavar="N", help="a LocalCluster of N worker processes")
    where.add_argument("--scheduler", help="address of a running Dask scheduler")
    where.add_argument("--slurm", type=int, metavar="N", help="N Slurm jobs of one worker each (dask-jobqueue)")
    p.add_argument("--chatter", default=shutil.which("chatter") or "chatter", help="the chatter binary")
    p.add_argument("--retries", type=int, default=3)
    a = p.parse_args()
    from contextlib import nullcontext

    from dask.distributed import Client, LocalCluster

    if a.local:
        cluster = LocalCluster(n_workers=a.local, threads_per_worker=1, processes=True, host="127.0.0.1",
                               dashboard_address=None)
    elif a.slurm:
        from dask_jobqueue import SLURMCluster
        cluster = SLURMCluster(cores=1, processes=1, memory="2GB", walltime="01:00:00")
        cluster.scale(jobs=a.slurm)
    else:
        cluster = None
    total = len(case_ids(a.study))
    with (cluster if cluster is not None else nullcontext()), Client(cluster or a.scheduler) as client:
        out = run_study(client, a.chatter, a.study, a.retries,
                        on_done=lambda i, n: print(f"[{n}/{total}] {i}", flush=True))
    print(out)

if __name__ == "__main__":
    main()
