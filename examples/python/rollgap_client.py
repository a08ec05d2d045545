#!/usr/bin/env python3
"""A small rollgap client for an MES or a script, on Python's standard library only.

    from rollgap_client import Rollgap, Problem
    api = Rollgap("http://localhost:8080")                  # token="..." with --token-file
    answer = api.analyse("stability", scenario={"rolls": {"speed_m_per_s": 15}})
    print(answer["result"]["critical_speed"]["critical_speed_m_per_s"])
    job = api.submit("sweep", options={"parameter": "/lubricant/viscosity_Pa_s",
                                        "values": [0.0004, 0.0007]})
    done = api.wait(job)                                    # polls as Retry-After says
    print(api.job_csv(done["id"]))                          # its table as CSV

Every refusal is raised as `Problem` with the service's RFC 9457 fields: the status, the
code, the detail and the errors (each with its JSON pointer, bound and unit). Run as a script
(`python3 rollgap_client.py http://localhost:8080`) it prints a stand's critical speed, runs a
sweep as a job to its end and prints the sweep's CSV.
"""

import json
import sys
import time
import urllib.error
import urllib.request

__all__ = ["Rollgap", "Problem"]

# The synchronous route of each analysis (the service's x-rollgap-analyses lists them too).
ROUTES = {
    "roll_gap": "/v1/roll-gap",
    "tension_cycle": "/v1/tension-cycle",
    "stability": "/v1/stability",
    "amplitude": "/v1/amplitude",
    "sweep": "/v1/sweeps",
    "map": "/v1/maps",
    "evaluate": "/v1/evaluate",
    "calibrate": "/v1/calibrate",
    "speed_limit": "/v1/speed-limit",
    "tandem": "/v1/tandem",
    "tandem_sweep": "/v1/tandem/sweeps",
    "tandem_map": "/v1/tandem/maps",
    "tandem_speed_limit": "/v1/tandem/speed-limit",
}

FINISHED = ("succeeded", "failed", "cancelled")


class Problem(Exception):
    """A refusal of the service: RFC 9457 problem details."""

    def __init__(self, status, document):
        self.status = status
        self.document = document if isinstance(document, dict) else {}
        self.code = self.document.get("code", "")
        self.detail = self.document.get("detail", "")
        self.errors = self.document.get("errors", [])
        lines = [f"{status} {self.code}: {self.detail}"]
        for error in self.errors:
            bound = f" (bound {error['bound']})" if error.get("bound") else ""
            unit = f" [{error['unit']}]" if error.get("unit") else ""
            lines.append(f"  {error.get('pointer', '')}: {error.get('detail', '')}{bound}{unit}")
        super().__init__("\n".join(lines))


class Rollgap:
    """The rollgap HTTP API (docs/http-api.md) at `base_url`."""

    def __init__(self, base_url, token=None, timeout_s=120.0):
        self.base_url = base_url.rstrip("/")
        self.token = token
        self.timeout_s = timeout_s

    # ---- the HTTP exchange ------------------------------------------------------------------

    def _request(self, method, path, body=None, accept="application/json", headers=None):
        data = None if body is None else json.dumps(body).encode("utf-8")
        request = urllib.request.Request(self.base_url + path, data=data, method=method)
        request.add_header("Accept", accept)
        if data is not None:
            request.add_header("Content-Type", "application/json")
        if self.token:
            request.add_header("Authorization", f"Bearer {self.token}")
        for name, value in (headers or {}).items():
            request.add_header(name, value)
        try:
            with urllib.request.urlopen(request, timeout=self.timeout_s) as response:
                return response.status, dict(response.headers), response.read()
        except urllib.error.HTTPError as error:
            text = error.read()
            try:
                document = json.loads(text)
            except ValueError:
                document = {"detail": text.decode("utf-8", "replace")}
            raise Problem(error.code, document) from None

    def _json(self, method, path, body=None, headers=None):
        status, response_headers, text = self._request(method, path, body, headers=headers)
        return status, response_headers, json.loads(text)

    # ---- analyses -----------------------------------------------------------------------------

    @staticmethod
    def _body(scenario=None, options=None, base=None, tandem=None):
        body = {}
        if scenario is not None:
            body["scenario"] = scenario
        if tandem is not None:
            body["tandem"] = tandem
        if options is not None:
            body["options"] = options
        if base is not None:
            body["base"] = base
        return body

    def analyse(self, analysis, scenario=None, options=None, base=None, tandem=None):
        """Runs `analysis` at once: its answer {analysis, scenario|tandem, options, result}."""
        body = self._body(scenario, options, base, tandem)
        return self._json("POST", ROUTES[analysis], body)[2]

    def csv(self, analysis, scenario=None, options=None, base=None, tandem=None, table=None):
        """The answer of `analysis` as one CSV table (`table`: which; None: the first)."""
        path = ROUTES[analysis] + (f"?table={table}" if table else "")
        body = self._body(scenario, options, base, tandem)
        return self._request("POST", path, body, accept="text/csv")[2].decode("utf-8")

    # ---- jobs ---------------------------------------------------------------------------------

    def submit(self, analysis, scenario=None, options=None, base=None, tandem=None,
               idempotency_key=None):
        """Queues `analysis` as a job; its document (id, state, ...). With an idempotency key a
        retry of the same submission returns the same job instead of a second one."""
        body = {"analysis": analysis, **self._body(scenario, options, base, tandem)}
        headers = {"Idempotency-Key": idempotency_key} if idempotency_key else None
        return self._json("POST", "/v1/jobs", body, headers=headers)[2]

    def job(self, job):
        """The job's current document (`job`: its id or its document)."""
        return self._json("GET", f"/v1/jobs/{self._id(job)}")[2]

    def wait(self, job, timeout_s=600.0, progress=None):
        """Polls the job until it has finished, as often as the service's Retry-After says
        (1 s when it says nothing); its last document. `progress(document)` is called at each
        poll. A job still running at `timeout_s` raises TimeoutError (it keeps running)."""
        until = time.monotonic() + timeout_s
        while True:
            _, headers, document = self._json("GET", f"/v1/jobs/{self._id(job)}")
            if progress:
                progress(document)
            if document["state"] in FINISHED:
                return document
            if time.monotonic() >= until:
                raise TimeoutError(f"job {self._id(job)} still {document['state']}")
            hint = headers.get("Retry-After", "1")
            time.sleep(min(float(hint) if hint.isdigit() else 1.0, max(until - time.monotonic(), 0)))

    def job_csv(self, job, table=None):
        """A succeeded job's result as one CSV table."""
        path = f"/v1/jobs/{self._id(job)}" + (f"?table={table}" if table else "")
        return self._request("GET", path, accept="text/csv")[2].decode("utf-8")

    def cancel(self, job):
        """Cancels a queued or running job, deletes a finished one; the job after it."""
        return self._json("DELETE", f"/v1/jobs/{self._id(job)}")[2]

    @staticmethod
    def _id(job):
        return job["id"] if isinstance(job, dict) else str(job)


def main(argv):
    if len(argv) != 2:
        print("usage: rollgap_client.py BASE_URL   (e.g. http://localhost:8080)", file=sys.stderr)
        return 2
    api = Rollgap(argv[1])
    answer = api.analyse("stability", scenario={"rolls": {"speed_m_per_s": 15}},
                         options={"detail": "summary"})
    search = answer["result"]["critical_speed"]
    print(f"critical speed: {search['critical_speed_m_per_s']:.3f} m/s ({search['status']})")
    job = api.submit("sweep", options={"parameter": "/lubricant/viscosity_Pa_s",
                                        "values": [0.0004, 0.0007]})
    done = api.wait(job)
    print(f"job {done['id']}: {done['state']}")
    print(api.job_csv(done), end="")
    return 0 if done["state"] == "succeeded" else 1


if __name__ == "__main__":
    sys.exit(main(sys.argv))
