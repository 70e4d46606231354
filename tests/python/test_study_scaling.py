"""A study run locally, in 3 shards, as a Slurm array (the shipped sbatch script, with the array
index set by hand) and on a Dask LocalCluster of 2 worker processes on the loopback interface,
one of which is killed mid-run, gives byte-identical collected results."""
import os
import signal
import subprocess
import sys
import time

import pytest

from conftest import ROOT

sys.path.insert(0, str(ROOT / "studies" / "chatter" / "dask"))
import chatter_dask  # noqa: E402

CHATTER = ROOT / "target" / "release" / "chatter"
ARGS = ["--seeds", "3", "--stop-time", "0.2", "--cases", "Open loop=off,ADRC-FOPID=adrc_fopid"]


def chatter(*args, env=None):
    if not CHATTER.exists():
        pytest.fail(f"{CHATTER} is missing: build it with `cargo build --release -p chatter`")
    r = subprocess.run([str(CHATTER), *map(str, args)], capture_output=True, text=True, env=env)
    assert r.returncode == 0, r.stderr
    return r.stdout


def collected(study):
    """Every file of the study folder but the case results (whose runs carry wall times)."""
    files = {}
    for p in sorted(study.rglob("*")):
        rel = p.relative_to(study)
        if p.is_file() and rel.parts[0] != "cases":
            files[str(rel)] = p.read_bytes()
    return files


@pytest.fixture(scope="module")
def local(tmp_path_factory):
    d = tmp_path_factory.mktemp("local")
    chatter("main-job", "--out", d, *ARGS)
    files = collected(d)
    assert "table5.md" in files and "runs_summary.csv" in files and "manifest.json" in files
    return files


def test_three_shards_equal_the_local_run(local, tmp_path):
    chatter("plan", "main-job", "--out", tmp_path, *ARGS)
    for i in (1, 2, 3):
        chatter("run", tmp_path, "--shard", f"{i}/3")
    chatter("collect", tmp_path)
    assert collected(tmp_path) == local


def test_the_slurm_array_script_runs_each_index_and_equals_the_local_run(local, tmp_path):
    chatter("plan", "main-job", "--out", tmp_path, *ARGS)
    n = len(chatter_dask.case_ids(tmp_path))
    script = ROOT / "studies" / "chatter" / "slurm" / "run_cases.sbatch"
    for k in range(n):
        env = dict(os.environ, SLURM_ARRAY_TASK_ID=str(k), CHATTER=str(CHATTER))
        subprocess.run(["bash", str(script), str(tmp_path)], check=True, env=env, capture_output=True)
    chatter("collect", tmp_path)
    assert collected(tmp_path) == local


def test_an_interrupted_run_completes_only_the_missing_cases(local, tmp_path):
    chatter("plan", "main-job", "--out", tmp_path, *ARGS)
    chatter("run", tmp_path, "--index", 0)
    out = chatter("run", tmp_path)
    assert "5 cases run, 1 already done, 0 failed" in out, out
    out = chatter("run", tmp_path)
    assert "0 cases run, 6 already done" in out, out
    chatter("collect", tmp_path)
    assert collected(tmp_path) == local


def test_dask_with_a_worker_killed_mid_run_equals_the_local_run(local, tmp_path):
    distributed = pytest.importorskip("dask.distributed")
    chatter("plan", "main-job", "--out", tmp_path, *ARGS)
    killed = []
    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True, host="127.0.0.1",
                                  dashboard_address=None) as cluster, distributed.Client(cluster) as client:
        pids = client.run(os.getpid)

        def kill_a_busy_worker():
            # wait until a worker is running a case, then SIGKILL its process (the nanny restarts it)
            for _ in range(500):
                busy = [w for w, tasks in client.processing().items() if tasks and w in pids]
                if busy:
                    os.kill(pids[busy[0]], signal.SIGKILL)
                    killed.append(busy[0])
                    return
                time.sleep(0.01)

        import threading
        t = threading.Thread(target=kill_a_busy_worker)
        t.start()
        chatter_dask.run_study(client, str(CHATTER), str(tmp_path), retries=3)
        t.join()
    assert killed, "no worker was busy"
    assert collected(tmp_path) == local
