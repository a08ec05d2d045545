#!/usr/bin/env python3
"""Figures of the shared job store on this machine (not a test: it prints measurements).

Starts a throw-away PostgreSQL 15 (as the `postgres` user when run as root) and `rollgap serve`
replicas on 127.0.0.1 sharing it, and prints:
  1. the wall time of a chunked critical-speed sweep job on one replica and on two, with the
     default threads and with one compute thread per replica (--workers 1 --analysis-threads 1);
  2. the time a replica's death (SIGKILL while the sweep runs) costs the sweep;
  3. the job store's overhead per job (submit -> succeeded of a trivial job vs the same analysis
     as a synchronous request) and per synchronous request without `base` (latency with the
     store's PostgreSQL running vs stopped).

Usage: python3 scripts/replica-figures.py [--rollgap build/rollgap] [--points 200] [--repeat 3]
Everything it starts is stopped and its temporary directory removed at the end.
"""

import argparse
import http.client
import json
import os
import re
import shutil
import signal
import socket
import statistics
import subprocess
import sys
import tempfile
import time

PG_BIN = "/usr/lib/postgresql/15/bin"


def free_port():
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def as_postgres(command):
    return (["runuser", "-u", "postgres", "--"] + command) if os.geteuid() == 0 else command


class Postgres:
    def __init__(self, directory):
        self.dir = directory
        self.port = free_port()
        os.chmod(directory, 0o777)
        subprocess.run(as_postgres([f"{PG_BIN}/initdb", "-D", f"{directory}/data", "--auth=trust",
                                    "-U", "postgres", "--no-sync"]),
                       check=True, stdout=subprocess.DEVNULL)
        self.start()
        subprocess.run([f"{PG_BIN}/createdb", "-h", "127.0.0.1", "-p", str(self.port), "-U",
                        "postgres", "figures"], check=True)
        self.dsn = f"postgresql://postgres@127.0.0.1:{self.port}/figures"

    def start(self):
        subprocess.run(as_postgres([f"{PG_BIN}/pg_ctl", "-D", f"{self.dir}/data", "-l",
                                    f"{self.dir}/server.log", "-w", "start", "-o",
                                    f"-p {self.port} -k {self.dir} -c listen_addresses=127.0.0.1"]),
                       check=True, stdout=subprocess.DEVNULL)

    def stop(self):
        subprocess.run(as_postgres([f"{PG_BIN}/pg_ctl", "-D", f"{self.dir}/data", "-m",
                                    "immediate", "-w", "stop"]),
                       check=False, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)

    def sql(self, statement):
        return subprocess.run([f"{PG_BIN}/psql", "-h", "127.0.0.1", "-p", str(self.port), "-U",
                               "postgres", "-d", "figures", "-At", "-c", statement],
                              check=True, capture_output=True, text=True).stdout


class Replica:
    def __init__(self, program, name, dsn, directory, extra):
        self.name = name
        self.log_path = os.path.join(directory, f"{name}-{time.monotonic_ns()}.log")
        log = open(self.log_path, "w")
        self.process = subprocess.Popen(
            [program, "serve", "--bind", "127.0.0.1", "--port", "0", "--admin-port", "0",
             "--instance", name, "--store", dsn, "--data-dir", os.path.join(directory, name),
             "--log-level", "info"] + extra,
            stdout=log, stderr=log)
        deadline = time.monotonic() + 20
        self.port = None
        while time.monotonic() < deadline and self.port is None:
            time.sleep(0.05)
            self.port = self._public_port()
        if self.port is None:
            self.kill()
            raise RuntimeError(f"replica {name} did not start: {open(self.log_path).read()}")
        self.connection = http.client.HTTPConnection("127.0.0.1", self.port, timeout=120)

    def _public_port(self):
        # `rollgap serve --log-level info` prints "address=127.0.0.1:P admin_address=...".
        text = open(self.log_path).read()
        found = re.search(r" address=127\.0\.0\.1:(\d+) admin_address", text)
        return int(found.group(1)) if found else None

    def request(self, method, path, body=None):
        headers = {"Content-Type": "application/json"} if body is not None else {}
        payload = json.dumps(body) if body is not None else None
        for attempt in range(2):
            try:
                self.connection.request(method, path, payload, headers)
                response = self.connection.getresponse()
                data = response.read()
                return response.status, (json.loads(data) if data else None)
            except (http.client.HTTPException, ConnectionError):
                self.connection.close()
                self.connection = http.client.HTTPConnection("127.0.0.1", self.port, timeout=120)
                if attempt == 1:
                    raise

    def kill(self):
        if self.process.poll() is None:
            self.process.send_signal(signal.SIGKILL)
            self.process.wait()

    def stop(self):
        if self.process.poll() is None:
            self.process.send_signal(signal.SIGTERM)
            try:
                self.process.wait(timeout=30)
            except subprocess.TimeoutExpired:
                self.kill()


def sweep_request(points):
    # The test's sweep (tests/system/test_replicas.cpp): critical speed over lubricant viscosity.
    return {"analysis": "sweep",
            "options": {"parameter": "/lubricant/viscosity_Pa_s",
                        "range": {"from": 0.00045, "to": 0.0007, "count": points},
                        "quantity": "critical_speed",
                        "critical_speed": {"speed_min_m_per_s": 17, "speed_max_m_per_s": 23,
                                           "relative_tolerance": 0.01}}}


def submit(replica, request):
    status, job = replica.request("POST", "/v1/jobs", request)
    if status not in (201, 202):
        raise RuntimeError(f"POST /v1/jobs: {status} {job}")
    return job["id"]


def wait_done(replica, job_id, poll=0.002, timeout=600, on_poll=None):
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        status, job = replica.request("GET", f"/v1/jobs/{job_id}")
        if status == 200 and job["state"] in ("succeeded", "failed", "cancelled"):
            return job
        if on_poll is not None and status == 200:
            on_poll(job)
        time.sleep(poll)
    raise RuntimeError(f"job {job_id} did not finish")


class Cluster:
    """Replicas started for one measurement and stopped after it (the database is emptied)."""

    def __init__(self, args, postgres, directory, count, extra):
        self.replicas = []
        if self._has_tables(postgres):
            postgres.sql("TRUNCATE jobs CASCADE")  # each measurement starts from an empty store
        for i in range(count):
            self.replicas.append(Replica(args.rollgap, "abcdefgh"[i], postgres.dsn, directory,
                                         ["--lease-ms", str(args.lease_ms),
                                          "--chunk-points", str(args.chunk_points)] + extra))

    @staticmethod
    def _has_tables(postgres):
        return postgres.sql("SELECT count(*) FROM pg_tables WHERE tablename = 'jobs'").strip() == "1"

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        for replica in self.replicas:
            replica.stop()


def timed_sweep(cluster, request, mark_at=None, kill=False):
    """Wall time of the sweep job submitted to the last replica, and the time at which
    `mark_at` of its points were done; with `kill`, the first replica is killed then."""
    survivor = cluster.replicas[-1]
    start = time.monotonic()
    job_id = submit(survivor, request)
    marked = {}

    def mark(job):
        if mark_at is not None and not marked and job.get("points_done", 0) >= mark_at:
            if kill:
                cluster.replicas[0].kill()
            marked["at"] = time.monotonic() - start
            marked["points_done"] = job.get("points_done", 0)

    job = wait_done(survivor, job_id, poll=0.01, on_poll=mark)
    elapsed = time.monotonic() - start
    if job["state"] != "succeeded":
        raise RuntimeError(f"sweep job {job['state']}: {job.get('problem')}")
    return elapsed, job, marked


def median_latency(replica, method, path, body, count):
    samples = []
    for _ in range(count):
        t = time.perf_counter()
        status, _ = replica.request(method, path, body)
        samples.append((time.perf_counter() - t) * 1000)
        if status != 200:
            raise RuntimeError(f"{method} {path}: {status}")
    return statistics.median(samples), sorted(samples)[int(0.9 * len(samples))]


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--rollgap", default="build/rollgap")
    parser.add_argument("--points", type=int, default=200)
    parser.add_argument("--chunk-points", type=int, default=10)
    parser.add_argument("--lease-ms", type=int, default=1500)
    parser.add_argument("--repeat", type=int, default=3)
    args = parser.parse_args()
    args.rollgap = os.path.abspath(args.rollgap)

    directory = tempfile.mkdtemp(prefix="rollgap-figures-")
    postgres = None
    try:
        postgres = Postgres(directory)
        print(f"machine: {os.cpu_count()} cores, load average {os.getloadavg()[0]:.1f} at start "
              f"(other work on the machine shows in the times)")
        request = sweep_request(args.points)
        print(f"sweep: {args.points} points (critical speed vs lubricant viscosity, 17-23 m/s, "
              f"1 % tolerance), chunks of {args.chunk_points}, lease {args.lease_ms} ms; "
              f"median of {args.repeat}")

        t = time.monotonic()
        subprocess.run([args.rollgap, "run", "-"], input=json.dumps(request), text=True,
                       check=True, stdout=subprocess.DEVNULL)
        print(f"  rollgap run (one process, no store): {time.monotonic() - t:.2f} s")

        for label, extra in (("default threads (--workers 2, analysis threads = cores)", []),
                             ("one thread per replica (--workers 1 --analysis-threads 1)",
                              ["--workers", "1", "--analysis-threads", "1"])):
            times = {}
            for count in (1, 2):
                runs = []
                for _ in range(args.repeat):
                    with Cluster(args, postgres, directory, count, extra) as cluster:
                        runs.append(timed_sweep(cluster, request)[0])
                times[count] = statistics.median(runs)
            print(f"  {label}: 1 replica {times[1]:.2f} s, 2 replicas {times[2]:.2f} s, "
                  f"speed-up {times[1] / times[2]:.2f}x")

        # Early, the survivor has other chunks to compute while the dead replica's lease runs
        # out; late, it has nothing else left and waits for the lease. The cost: the time from
        # the kill to the end, minus the same stretch of an undisturbed run (from the moment
        # as many points were done), medians.
        for share in (30, 80):
            tails = {}
            for kill in (False, True):
                runs = []
                for _ in range(args.repeat):
                    with Cluster(args, postgres, directory, 2, []) as cluster:
                        elapsed, _, marked = timed_sweep(cluster, request,
                                                         args.points * share // 100, kill)
                        if marked:
                            runs.append(elapsed - marked["at"])
                tails[kill] = statistics.median(runs) if runs else float("nan")
            print(f"kill -9 of one of 2 replicas once {share} % of the points are done: the rest "
                  f"took {tails[True]:.2f} s vs {tails[False]:.2f} s undisturbed: the death cost "
                  f"{tails[True] - tails[False]:+.2f} s (lease {args.lease_ms / 1000:.1f} s, "
                  f"chunks of {args.chunk_points} points)")

        with Cluster(args, postgres, directory, 1, []) as cluster:
            replica = cluster.replicas[0]
            body = {"options": {"distributions": False}}
            job_request = dict(body, analysis="roll_gap")
            sync_ms, sync_p90 = median_latency(replica, "POST", "/v1/roll-gap", body, 200)
            job_ms = []
            for _ in range(30):
                t = time.perf_counter()
                job_id = submit(replica, job_request)
                wait_done(replica, job_id, poll=0.001)
                job_ms.append((time.perf_counter() - t) * 1000)
            job_median = statistics.median(job_ms)
            print(f"trivial analysis (roll_gap, no distributions): synchronous {sync_ms:.2f} ms "
                  f"median; as a job, submit -> succeeded {job_median:.2f} ms median "
                  f"(polling every 1 ms): store overhead per job {job_median - sync_ms:.2f} ms")

            up_ms, up_p90 = median_latency(replica, "POST", "/v1/roll-gap", body, 300)
            postgres.stop()
            time.sleep(0.5)
            down_ms, down_p90 = median_latency(replica, "POST", "/v1/roll-gap", body, 300)
            postgres.start()
            print(f"synchronous POST /v1/roll-gap without base, 300 requests: PostgreSQL running "
                  f"{up_ms:.2f} ms median ({up_p90:.2f} p90), stopped {down_ms:.2f} ms median "
                  f"({down_p90:.2f} p90)")
    finally:
        if postgres is not None:
            postgres.stop()
        shutil.rmtree(directory, ignore_errors=True)


if __name__ == "__main__":
    sys.exit(main())
