#!/usr/bin/env python3
"""Static checks of the Kubernetes files in deploy/ (no cluster, no kubectl needed).

    python3 deploy/check.py

Every YAML file parses; every resource and generator file a kustomization lists exists; and
the properties docs/operations.md promises hold: no session affinity, a PodDisruptionBudget
selecting the pods, the job store's DSN read from a mounted Secret that the trial database
provides, the bearer token from a mounted Secret too (no secret in the environment), a
Service that targets nginx's port and a service container that runs the service alone on the
pod's loopback, a writable data directory on the read-only root filesystem, and a grace period that
covers the preStop pause, the drain timeout and the exit. With kubectl on the PATH it also
builds both kustomizations (`kubectl kustomize`, offline). Exit status 0 when every check passes.
"""
import pathlib
import re
import shutil
import subprocess
import sys

import yaml

DEPLOY = pathlib.Path(__file__).resolve().parent
failures = []


def check(condition, message):
    if not condition:
        failures.append(message)
    return condition


def documents(path):
    with open(path, encoding="utf-8") as f:
        return [d for d in yaml.safe_load_all(f) if d is not None]


# 1. Every YAML file parses.
parsed = {}
for path in sorted(DEPLOY.rglob("*.yaml")):
    try:
        parsed[path] = documents(path)
    except yaml.YAMLError as e:
        check(False, f"{path.relative_to(DEPLOY)}: not valid YAML: {e}")

# 2. Every file a kustomization lists exists; collect the objects it deploys.
def kustomization_objects(path):
    (k,) = parsed[path]
    objects = []
    for resource in k.get("resources", []):
        target = path.parent / resource
        if check(target.is_file(), f"{path.relative_to(DEPLOY)}: resource {resource} does not exist"):
            objects += parsed.get(target, [])
    for generator in k.get("configMapGenerator", []) + k.get("secretGenerator", []):
        for entry in generator.get("files", []):
            source = entry.split("=", 1)[-1]
            check((path.parent / source).is_file(),
                  f"{path.relative_to(DEPLOY)}: generator file {source} does not exist")
    return objects


main = kustomization_objects(DEPLOY / "kustomization.yaml")
trial = kustomization_objects(DEPLOY / "kubernetes/postgres/kustomization.yaml")


def find(objects, kind, name=None):
    found = [o for o in objects if o.get("kind") == kind and (name is None or o["metadata"]["name"] == name)]
    return found[0] if found else None


deployment = find(main, "Deployment", "rollgap")
service = find(main, "Service", "rollgap")
pdb = find(main, "PodDisruptionBudget")
check(deployment is not None, "deploy/kustomization.yaml deploys no Deployment rollgap")
check(service is not None, "deploy/kustomization.yaml deploys no Service rollgap")

# 3. No session affinity: any replica answers any job.
if service:
    check(service["spec"].get("sessionAffinity", "None") == "None",
          "the Service still has session affinity")

if deployment:
    pod = deployment["spec"]["template"]["spec"]
    labels = deployment["spec"]["template"]["metadata"]["labels"]
    rollgap = next(c for c in pod["containers"] if c["name"] == "rollgap")
    env = {e["name"]: e for e in rollgap.get("env", [])}
    mounts = {m["mountPath"]: m for m in rollgap.get("volumeMounts", [])}
    volumes = {v["name"]: v for v in pod.get("volumes", [])}

    # 4. A PodDisruptionBudget that selects these pods.
    if check(pdb is not None, "no PodDisruptionBudget"):
        selector = pdb["spec"]["selector"]["matchLabels"]
        check(all(labels.get(k) == v for k, v in selector.items()),
              "the PodDisruptionBudget does not select the Deployment's pods")
        check(("minAvailable" in pdb["spec"]) != ("maxUnavailable" in pdb["spec"]),
              "the PodDisruptionBudget needs exactly one of minAvailable, maxUnavailable")

    # 5. The store's DSN from a file on a mounted Secret, which the trial database creates.
    store = env.get("ROLLGAP_STORE", {}).get("value", "")
    if check(store.startswith("postgresql-file:"), f"ROLLGAP_STORE is {store!r}, not postgresql-file:"):
        dsn_path = pathlib.PurePosixPath(store.split(":", 1)[1])
        mount = mounts.get(str(dsn_path.parent))
        if check(mount is not None, f"nothing is mounted at {dsn_path.parent}"):
            volume = volumes.get(mount["name"], {})
            secret = volume.get("secret")
            if check(secret is not None, f"{dsn_path.parent} is not a Secret volume"):
                items = {i["path"]: i["key"] for i in secret.get("items", [])}
                key = items.get(dsn_path.name, dsn_path.name)
                provided = find(trial, "Secret", secret["secretName"])
                if check(provided is not None,
                         f"the trial database creates no Secret {secret['secretName']}"):
                    data = provided.get("stringData", {})
                    check(re.match(r"^postgresql://[^@\s]+@[^/\s]+/\S+$", data.get(key, "")) is not None,
                          f"Secret {secret['secretName']} has no postgresql:// DSN under key {key}")
                    host = re.match(r"^postgresql://[^@]+@([^:/]+)", data.get(key, ""))
                    check(host is not None and find(trial, "Service", host.group(1)) is not None,
                          "the trial DSN's host is not the trial database's Service")

    # 5b. No secret in the environment (it would show in the pod's spec and in `kubectl
    # describe`): the bearer token, like the DSN, from a file on a mounted Secret, required.
    for name, e in env.items():
        check("secretKeyRef" not in e.get("valueFrom", {}),
              f"{name} comes from a Secret through the environment, not a mounted file")
    check("ROLLGAP_TOKEN" not in env, "ROLLGAP_TOKEN is set in the environment")
    token = env.get("ROLLGAP_TOKEN_FILE", {}).get("value", "")
    if check(token != "", "ROLLGAP_TOKEN_FILE is not set: the compute endpoints take anyone"):
        token_path = pathlib.PurePosixPath(token)
        mount = mounts.get(str(token_path.parent))
        if check(mount is not None and mount.get("readOnly", False),
                 f"no read-only mount at {token_path.parent}"):
            secret = volumes.get(mount["name"], {}).get("secret")
            if check(secret is not None, f"{token_path.parent} is not a Secret volume"):
                items = {i["path"]: i["key"] for i in secret.get("items", [])}
                check(token_path.name in items or not items,
                      f"the Secret {secret['secretName']} puts no file {token_path.name} there")
                check(not secret.get("optional", False),
                      f"the Secret {secret['secretName']} is optional: a pod without it would serve "
                      "without a token")

    # 5c. The Service reaches the pods through nginx: its targetPort is a port of the nginx
    # container, never the service's own (loopback) or admin listener; the rollgap container
    # runs the service alone (the image's default command would start a second nginx).
    if service:
        nginx = next((c for c in pod["containers"] if c["name"] == "nginx"), None)
        if check(nginx is not None, "the pod has no nginx container"):
            nginx_ports = {p.get("name"): p["containerPort"] for p in nginx.get("ports", [])}
            for port in service["spec"]["ports"]:
                target = port.get("targetPort", port["port"])
                check(target in nginx_ports or target in nginx_ports.values(),
                      f"the Service's port {port['port']} targets {target!r}, not a port of nginx")
        check(rollgap.get("command", [None])[0] == "/usr/local/bin/rollgap"
              and rollgap.get("args") == ["serve"],
              "the rollgap container does not run /usr/local/bin/rollgap serve")
        check(env.get("ROLLGAP_BIND", {}).get("value") == "127.0.0.1",
              "the rollgap container's service does not listen on the pod's loopback only")

    # 6. A writable data directory on the read-only root filesystem.
    data_dir = env.get("ROLLGAP_DATA_DIR", {}).get("value")
    if check(data_dir is not None, "ROLLGAP_DATA_DIR is not set"):
        mount = mounts.get(data_dir)
        check(mount is not None and not mount.get("readOnly", False)
              and "emptyDir" in volumes.get(mount["name"], {}),
              f"the data directory {data_dir} is not a writable emptyDir")
    for name in ("ROLLGAP_LEASE_MS", "ROLLGAP_CHUNK_POINTS"):
        check(str(env.get(name, {}).get("value", "")).isdigit(), f"{name} is not set to a number")

    # 7. The grace period covers preStop + drain timeout + 2 s exit (docs/operations.md:
    # "Logs, metrics, health, shutdown").
    pause = 0
    for c in pod["containers"]:
        command = " ".join(c.get("lifecycle", {}).get("preStop", {}).get("exec", {}).get("command", []))
        m = re.search(r"sleep\s+(\d+)", command)
        if c["name"] == "rollgap" and m:
            pause = int(m.group(1))
    drain_s = int(env["ROLLGAP_DRAIN_TIMEOUT_MS"]["value"]) / 1000
    grace = pod.get("terminationGracePeriodSeconds", 30)
    check(grace >= pause + drain_s + 2,
          f"terminationGracePeriodSeconds {grace} < preStop {pause} + drain {drain_s:g} + 2 s")

# 8. With kubectl, both kustomizations build.
kubectl = shutil.which("kubectl")
if kubectl:
    for directory in (DEPLOY, DEPLOY / "kubernetes/postgres"):
        run = subprocess.run([kubectl, "kustomize", str(directory)], capture_output=True, text=True)
        check(run.returncode == 0, f"kubectl kustomize {directory}: {run.stderr.strip()}")

for f in failures:
    print("deploy/check.py: FAIL:", f, file=sys.stderr)
print(f"deploy/check.py: {len(parsed)} YAML files, {'kubectl kustomize too' if kubectl else 'no kubectl'}: "
      f"{'OK' if not failures else str(len(failures)) + ' failure(s)'}")
sys.exit(1 if failures else 0)
