#!/usr/bin/env python3
"""RSS of `rollgap serve` under a Range flood (8 clients asking 2,700 ranges and not reading) and under
header floods (10^6 fields; one 64 MB line), and its exit time after SIGTERM under load with a slow
client attached. Usage: scripts/http-hardening-figures.py build/rollgap range|headers|drain"""
import os, socket, subprocess, sys, threading, time, json

def free_port():
    s = socket.socket(); s.bind(("127.0.0.1", 0)); p = s.getsockname()[1]; s.close(); return p

def rss_mb(pid):
    with open(f"/proc/{pid}/status") as f:
        for line in f:
            if line.startswith("VmRSS:"):
                return int(line.split()[1]) / 1024.0
    return -1

def start(binary, extra):
    port = free_port(); admin = free_port()
    env = dict(os.environ, ROLLGAP_LOG_LEVEL="warn")
    args = [binary, "serve", "--port", str(port), "--workers", "2", "--io-threads", "16"] + extra
    if "admin" in open(binary, "rb").read().decode("latin1") and b"--admin-port" in open(binary, "rb").read():
        args += ["--admin-port", str(admin)]
    p = subprocess.Popen(args, env=env, stderr=subprocess.DEVNULL)
    for _ in range(200):
        try:
            socket.create_connection(("127.0.0.1", port), timeout=0.2).close(); break
        except OSError: time.sleep(0.05)
    return p, port

def range_case(binary):
    p, port = start(binary, [])
    base = rss_mb(p.pid)
    ranges = "bytes=0-" + ",0-" * 2699
    socks = []
    for _ in range(8):
        s = socket.create_connection(("127.0.0.1", port))
        s.setsockopt(socket.SOL_SOCKET, socket.SO_RCVBUF, 4096)
        s.sendall(f"GET /openapi.json HTTP/1.1\r\nHost: x\r\nRange: {ranges}\r\n\r\n".encode())
        socks.append(s)
    time.sleep(6)
    peak = rss_mb(p.pid)
    # one client that reads: how big is the answer?
    s = socket.create_connection(("127.0.0.1", port)); s.settimeout(20)
    s.sendall(f"GET /openapi.json HTTP/1.1\r\nHost: x\r\nConnection: close\r\nRange: {ranges}\r\n\r\n".encode())
    total = 0
    try:
        while True:
            d = s.recv(1 << 20)
            if not d: break
            total += len(d)
    except socket.timeout: pass
    for s in socks: s.close()
    p.terminate(); p.wait(timeout=60)
    print(f"range: rss start {base:.1f} MB, with 8 non-reading clients {peak:.1f} MB; one answer {total} bytes")

def headers_case(binary):
    p, port = start(binary, [])
    base = rss_mb(p.pid)
    s = socket.create_connection(("127.0.0.1", port)); s.settimeout(30)
    status = b""
    try:
        s.sendall(b"GET /livez HTTP/1.1\r\nHost: x\r\n")
        chunk = b"".join(b"X-%07d: v\r\n" % i for i in range(10000))
        for _ in range(100):  # 1,000,000 header fields, ~14 MB
            s.sendall(chunk)
        s.sendall(b"\r\n")
        status = s.recv(64)
    except OSError as e:
        try: status = s.recv(64)
        except OSError: status = repr(e).encode()
    s.close()
    time.sleep(1)
    after_many = rss_mb(p.pid)
    s = socket.create_connection(("127.0.0.1", port)); s.settimeout(30)
    status2 = b""
    try:
        s.sendall(b"GET /livez HTTP/1.1\r\nHost: x\r\nX-Big: ")
        big = b"a" * (1 << 20)
        for _ in range(64):
            s.sendall(big)
        s.sendall(b"\r\n\r\n")
        status2 = s.recv(64)
    except OSError as e:
        try: status2 = s.recv(64)
        except OSError: status2 = repr(e).encode()
    s.close()
    time.sleep(1)
    after_big = rss_mb(p.pid)
    p.terminate(); p.wait(timeout=60)
    first = status.split(b"\r")[0]; second = status2.split(b"\r")[0]
    print(f"headers: rss start {base:.1f} MB; after 1e6 header fields {after_many:.1f} MB ({first!r}); "
          f"after a 64 MB header line {after_big:.1f} MB ({second!r})")

def drain_case(binary):
    p, port = start(binary, ["--drain-timeout-ms", "2000", "--queue-length", "8"])
    stop = threading.Event(); statuses = {}
    lock = threading.Lock()
    body = json.dumps({"options": {"parameter": "/lubricant/viscosity_Pa_s",
                                   "range": {"from": 0.0004, "to": 0.0008, "count": 200}}}).encode()
    def load():
        while not stop.is_set():
            try:
                s = socket.create_connection(("127.0.0.1", port), timeout=2); s.settimeout(60)
                s.sendall(b"POST /v1/sweeps HTTP/1.1\r\nHost: x\r\nContent-Type: application/json\r\nContent-Length: %d\r\n\r\n" % len(body) + body)
                d = s.recv(64); s.close()
                code = d[9:12].decode() if d else "none"
            except OSError:
                code = "no answer (refused after exit, or reset)"
            with lock: statuses[code] = statuses.get(code, 0) + 1
    threads = [threading.Thread(target=load) for _ in range(8)]
    for t in threads: t.start()
    def loris():
        try:
            s = socket.create_connection(("127.0.0.1", port))
            for c in b"GET /livez HTTP/1.1\r\nHost: x\r\nX-Slow: " + b"a" * 1000:
                if stop.is_set(): break
                s.send(bytes([c])); time.sleep(1)
        except OSError: pass
    lt = threading.Thread(target=loris); lt.start()
    time.sleep(4)
    t0 = time.monotonic(); p.send_signal(15)
    try:
        p.wait(timeout=120); exit_s = f"{time.monotonic() - t0:.2f}"
    except subprocess.TimeoutExpired:
        exit_s = "more than 120"
    stop.set()
    p.wait(timeout=300)
    for t in threads: t.join()
    lt.join(timeout=2)
    print(f"drain: exit {exit_s} s after SIGTERM (drain timeout 2 s, 8 clients posting sweeps, 1 slow client); "
          f"exit status {p.returncode}; answers {statuses}")

{"range": range_case, "headers": headers_case, "drain": drain_case}[sys.argv[2]](sys.argv[1])
