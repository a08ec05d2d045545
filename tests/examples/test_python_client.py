#!/usr/bin/env python3
"""The stdlib-only example client (examples/python/rollgap_client.py) against a live service.

Starts `rollgap serve` on a loopback port the OS picks (a job store of its own), then with the
client: a stand's stability answer (equal to the same request posted by hand), a refusal raised
as Problem with its pointer, bound and unit, a sweep run as a job and polled to its end (the
poll hint honoured), its CSV whose rows are the job's points, and the example's own main().
usage: test_python_client.py path/to/rollgap
"""

import csv
import io
import json
import os
import re
import shutil
import subprocess
import sys
import tempfile
import time
import urllib.request

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, "..", "..", "examples", "python"))
import rollgap_client  # noqa: E402
from rollgap_client import Problem, Rollgap  # noqa: E402


def start(binary, data_dir):
    process = subprocess.Popen(
        [binary, "serve", "--bind", "127.0.0.1", "--port", "0", "--workers", "2",
         "--data-dir", data_dir],
        stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
    deadline = time.monotonic() + 20
    log = ""
    while time.monotonic() < deadline:
        line = process.stderr.readline()
        if not line:
            break
        log += line
        match = re.search(r"address=127\.0\.0\.1:(\d+)", line)
        if match:
            return process, f"http://127.0.0.1:{match.group(1)}"
    process.kill()
    raise SystemExit(f"rollgap serve did not listen within 20 s:\n{log}")


def check(condition, what):
    if not condition:
        raise AssertionError(what)
    print(f"ok - {what}")


def main(binary):
    data_dir = tempfile.mkdtemp(prefix="rollgap-python-")
    process, base = start(binary, data_dir)
    try:
        api = Rollgap(base)
        scenario = {"rolls": {"speed_m_per_s": 15}}
        options = {"detail": "summary"}
        answer = api.analyse("stability", scenario=scenario, options=options)
        by_hand = json.loads(urllib.request.urlopen(urllib.request.Request(
            base + "/v1/stability", method="POST",
            data=json.dumps({"scenario": scenario, "options": options}).encode(),
            headers={"Content-Type": "application/json"})).read())
        check(answer == by_hand, "a stability answer is the route's answer")
        speed = answer["result"]["critical_speed"]["critical_speed_m_per_s"]
        check(isinstance(speed, float) and speed > 0, f"a critical speed: {speed:.3f} m/s")

        try:
            api.analyse("roll_gap", scenario={"strip": {"reduction": 25}})
            check(False, "an invalid reduction is refused")
        except Problem as problem:
            check(problem.status == 422 and problem.code == "invalid_scenario",
                  "a refusal is raised as Problem 422 invalid_scenario")
            first = problem.errors[0]
            check(first["pointer"] == "/scenario/strip/reduction" and first.get("bound"),
                  f"naming the field and its bound: {first['pointer']} {first['bound']}")
            check("/scenario/strip/reduction" in str(problem), "the message names the pointer")

        values = [0.0004, 0.0007]
        job = api.submit("sweep", options={"parameter": "/lubricant/viscosity_Pa_s",
                                            "values": values})
        check(job["state"] in ("queued", "running", "succeeded"), f"a job queued: {job['id']}")
        polls = []
        done = api.wait(job, timeout_s=120, progress=polls.append)
        check(done["state"] == "succeeded", f"polled to its end in {len(polls)} polls")
        points = done["result"]["result"]["points"]
        table = list(csv.DictReader(io.StringIO(api.job_csv(done))))
        check(len(table) == len(values) == len(points), "its CSV has one row per swept value")
        for row, point, value in zip(table, points, values):
            check(float(row["value_Pa_s"]) == value, f"row value {row['value_Pa_s']} Pa.s")
            check(float(row["critical_speed_m_per_s"]) == point["critical_speed_m_per_s"],
                  f"row critical speed {row['critical_speed_m_per_s']} m/s is the job's")
        check(api.cancel(done)["deleted"] is True, "a finished job deleted")

        # The example as a script prints the same critical speed and the CSV.
        output = io.StringIO()
        saved, sys.stdout = sys.stdout, output
        try:
            status = rollgap_client.main(["rollgap_client.py", base])
        finally:
            sys.stdout = saved
        text = output.getvalue()
        check(status == 0, "the example's main() succeeds")
        check(f"{speed:.3f} m/s" in text, "and prints the critical speed")
        check("critical_speed_m_per_s" in text.splitlines()[2], "and the sweep's CSV")
    finally:
        process.terminate()
        try:
            process.wait(timeout=30)
        except subprocess.TimeoutExpired:
            process.kill()
        shutil.rmtree(data_dir, ignore_errors=True)
    return 0


if __name__ == "__main__":
    if len(sys.argv) != 2:
        raise SystemExit("usage: test_python_client.py path/to/rollgap")
    sys.exit(main(sys.argv[1]))
