#!/usr/bin/env python3
"""The loopback cluster: Debian's nginx, run as an ordinary process through the repository's
docker/nginx-entrypoint.sh (configuration rendered from docker/nginx.conf.template for 127.0.0.1
ports, self-signed certificate made on first start), in front of three `penumbra serve` replicas
that share a cluster secret and an access token; real WebSocket clients (python3-websocket).

Each check prints what it saw; the first failure ends the run with status 1. With --measure, the
proxy's added latency (`penumbra load` through nginx and direct, same run) is printed as well.

With --node, the web client (client_web/dist, served by the replicas) runs in Debian's chromium
through the proxy while a replica is killed under it (browser_failover.mjs).

usage: cluster_test.py --penumbra BIN --source DIR --work DIR [--measure SECONDS] [--node NODE]
"""

import argparse
import itertools
import json
import os
import queue
import shutil
import signal
import socket
import ssl
import struct
import subprocess
import sys
import threading
import time
import urllib.parse
import urllib.request

import websocket

PING_INTERVAL_S = 0.5
PING_TIMEOUT_S = 1.0
PROXY_READ_TIMEOUT_S = 3
# Small volumes from Debian's mricron-data: a volume is read once per replica that opens it.
VOLUMES = ["JHU-WhiteMatter-labels-2mm.nii.gz", "AICHAmc.nii.gz", "aal.nii.gz", "brodmann.nii.gz"]
TEMPLATES = "/usr/share/mricron/templates"
# Characters that must be percent-encoded in a URL, as a real token may hold.
TOKEN = "cluster+test/token=7f3a"
SIZE = [64, 64]


class CheckFailed(Exception):
    pass


def check(condition, what):
    if not condition:
        raise CheckFailed(what)
    print(f"  ok: {what}", flush=True)


def free_port():
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def wait_for_port(port, deadline_s, process=None):
    end = time.monotonic() + deadline_s
    while time.monotonic() < end:
        if process is not None and process.poll() is not None:
            raise CheckFailed(f"process on port {port} exited with {process.returncode}")
        try:
            with socket.create_connection(("127.0.0.1", port), timeout=0.5):
                return
        except OSError:
            time.sleep(0.1)
    raise CheckFailed(f"nothing listens on port {port} after {deadline_s} s")


def metrics(port):
    """{name: value} of a replica's /metrics (samples without labels)."""
    with urllib.request.urlopen(f"http://127.0.0.1:{port}/metrics", timeout=5) as response:
        text = response.read().decode()
    values = {}
    for line in text.splitlines():
        if line and not line.startswith("#") and "{" not in line:
            name, value = line.split()[:2]
            values[name] = float(value)
    return values


class Replica:
    def __init__(self, args, work, index, secret_file, token_file, data):
        self.index = index
        self.port = free_port()
        self.log_path = os.path.join(work, f"replica{index}.log")
        self.command = [
            args.penumbra, "serve", "--data", data, "--address", "127.0.0.1",
            "--port", str(self.port), "--no-quality-measure", "--max-image-side", "256",
            # `penumbra load` sends a set and a render per frame, faster than the default limit.
            "--max-requests-per-second", "5000",
            "--cluster-secret-file", secret_file, "--access-token-file", token_file,
            "--allowed-origins", "https://app.example",
            "--ping-interval", str(PING_INTERVAL_S), "--ping-timeout", str(PING_TIMEOUT_S)]
        self.process = None

    def start(self):
        self.log = open(self.log_path, "w")
        self.process = subprocess.Popen(self.command, stdout=self.log, stderr=subprocess.STDOUT)

    def kill(self):
        self.process.send_signal(signal.SIGKILL)
        self.process.wait()

    def stop(self):
        if self.process and self.process.poll() is None:
            self.process.terminate()
            try:
                self.process.wait(10)
            except subprocess.TimeoutExpired:
                self.process.kill()
                self.process.wait()


class Client:
    """A WebSocket client whose reader thread answers pings (websocket-client does so inside
    recv) until freeze(), like a client whose machine went to sleep."""

    id_bases = itertools.count(1, 1_000_000)

    def __init__(self, url, **options):
        self.ws = websocket.create_connection(url, timeout=10, **options)
        self.ws.settimeout(None)
        self.inbox = queue.Queue()
        self.closed = threading.Event()
        # Ids apart from every other client's, so that a frame's request names its sender.
        self.next_id = next(Client.id_bases)
        self.renders = set()
        threading.Thread(target=self._read, daemon=True).start()
        hello = self.expect(lambda m: m.get("type") == "hello", 10)
        if hello.get("server") != "penumbra":
            raise CheckFailed(f"not a penumbra hello: {hello}")

    def _read(self):
        try:
            while True:
                opcode, data = self.ws.recv_data()
                if opcode == websocket.ABNF.OPCODE_TEXT:
                    self.inbox.put(json.loads(data.decode()))
                elif opcode == websocket.ABNF.OPCODE_BINARY:
                    self.inbox.put(parse_frame(data))
                elif opcode == websocket.ABNF.OPCODE_CLOSE:
                    break
        except Exception:  # the connection went away: what closed() reports
            pass
        self.closed.set()
        self.inbox.put(None)

    def freeze(self):
        # websocket-client answers a ping inside recv, wherever the reader waits: it answers no
        # more from now on, and sends nothing else either.
        self.ws.pong = lambda payload="": None

    def send(self, message):
        message = dict(message, v=1, id=self.next_id)
        self.next_id += 1
        self.ws.send(json.dumps(message))
        return message["id"]

    def expect(self, predicate, timeout_s):
        end = time.monotonic() + timeout_s
        while True:
            left = end - time.monotonic()
            if left <= 0:
                raise CheckFailed("no expected message in time")
            try:
                message = self.inbox.get(timeout=left)
            except queue.Empty:
                continue
            if message is None:
                self.inbox.put(None)
                raise ConnectionError("the connection closed")
            if predicate(message):
                return message

    def request(self, message, timeout_s=15):
        request_id = self.send(message)
        return self.expect(lambda m: m.get("id") == request_id and "frame" not in m, timeout_s)

    def frame(self, timeout_s=15):
        """Asks for a frame and waits for it, or for the frame of another connection's render
        of the session that superseded it (renders are coalesced, latest wins)."""
        request_id = self.send({"type": "render"})
        self.renders.add(request_id)
        return self.expect(lambda m: "frame" in m and (m["frame"]["request"] == request_id
                                                       or m["frame"]["request"] not in self.renders),
                           timeout_s)

    def any_frame(self, timeout_s=15):
        return self.expect(lambda m: "frame" in m, timeout_s)

    def close(self):
        try:
            self.ws.close(timeout=1)
        except Exception:
            pass


def parse_frame(data):
    magic, _version, header_length = struct.unpack_from("<4sHI", data, 0)
    if magic != b"PNBF":
        raise ValueError("not a frame")
    return {"frame": json.loads(data[10:10 + header_length].decode()),
            "image_bytes": len(data) - 10 - header_length}


class Cluster:
    def __init__(self, args):
        self.args = args
        self.work = args.work
        shutil.rmtree(self.work, ignore_errors=True)
        os.makedirs(self.work)
        self.data = os.path.join(self.work, "data")
        os.makedirs(self.data)
        for name in VOLUMES:
            # Copies: the server offers no symbolic links.
            shutil.copy(os.path.join(TEMPLATES, name), os.path.join(self.data, name))
        secret_file = os.path.join(self.work, "cluster.secret")
        self.token_file = os.path.join(self.work, "access.token")
        with open(secret_file, "w") as f:
            f.write(os.urandom(24).hex() + "\n")
        with open(self.token_file, "w") as f:
            f.write(TOKEN + "\n")
        self.replicas = [Replica(args, self.work, i, secret_file, self.token_file, self.data)
                         for i in range(3)]
        self.http_port = free_port()
        self.https_port = free_port()
        self.tls = os.path.join(self.work, "tls")
        self.nginx = None

    def start(self):
        for replica in self.replicas:
            replica.start()
        for replica in self.replicas:
            wait_for_port(replica.port, 60, replica.process)
        state = os.path.join(self.work, "nginx")
        os.makedirs(state)
        env = dict(os.environ,
                   PENUMBRA_UPSTREAMS=" ".join(f"127.0.0.1:{r.port}" for r in self.replicas),
                   PENUMBRA_HTTP_PORT=str(self.http_port),
                   PENUMBRA_HTTPS_PORT=str(self.https_port),
                   # The plain port is proxied too, for `penumbra load` (no TLS in it).
                   PENUMBRA_PLAIN_HTTP="proxy",
                   PENUMBRA_TLS_CERT=os.path.join(self.tls, "tls.crt"),
                   PENUMBRA_TLS_KEY=os.path.join(self.tls, "tls.key"),
                   PENUMBRA_PROXY_READ_TIMEOUT=f"{PROXY_READ_TIMEOUT_S}s",
                   PENUMBRA_PROXY_CONNECT_TIMEOUT="1s",
                   PENUMBRA_NGINX_STATE_DIR=state,
                   PENUMBRA_NGINX_WORKERS="1",
                   PENUMBRA_NGINX_CONF=os.path.join(state, "nginx.conf"),
                   PENUMBRA_NGINX_ACCESS_LOG=os.path.join(state, "access.log"),
                   PENUMBRA_NGINX_ERROR_LOG=os.path.join(state, "error.log"))
        self.nginx_log = open(os.path.join(self.work, "nginx.out"), "w")
        self.nginx = subprocess.Popen(
                [os.path.join(self.args.source, "docker", "nginx-entrypoint.sh")], env=env,
                stdout=self.nginx_log, stderr=subprocess.STDOUT)
        wait_for_port(self.https_port, 30, self.nginx)
        wait_for_port(self.http_port, 30, self.nginx)

    def stop(self):
        if self.nginx and self.nginx.poll() is None:
            self.nginx.terminate()
            self.nginx.wait(10)
        for replica in self.replicas:
            replica.stop()

    def url(self, volume, tls=False, token=TOKEN, **extra):
        query = {"volume": volume}
        query.update(extra)
        if token is not None:
            query["token"] = token
        scheme, port = ("wss", self.https_port) if tls else ("ws", self.http_port)
        # As browsers encode it (proto/README.md §1): '*' kept, '~' escaped.
        encoded = urllib.parse.urlencode(query, safe="*", quote_via=urllib.parse.quote_plus)
        return f"{scheme}://127.0.0.1:{port}/ws?{encoded.replace('~', '%7E')}"

    def live(self):
        return [r for r in self.replicas if r.process.poll() is None]

    def holder_of_sessions(self, count):
        """The one live replica holding `count` sessions while the others hold none."""
        seen = {r.index: metrics(r.port).get("penumbra_sessions", 0) for r in self.live()}
        holders = [i for i, n in seen.items() if n > 0]
        check(len(holders) == 1 and seen[holders[0]] == count,
              f"{count} sessions of one volume on one replica ({seen})")
        return self.replicas[holders[0]]

    def total(self, name):
        return sum(metrics(r.port).get(name, 0) for r in self.live())

    def loads(self):
        return {r.index: metrics(r.port).get("penumbra_volume_loads", 0) for r in self.live()}


def open_session(client, volume, state_patch=None):
    opened = client.request({"type": "open", "volume": volume})
    if opened.get("type") != "opened":
        raise CheckFailed(f"open {volume}: {opened}")
    patch = {"settings": {"size": SIZE}}
    if state_patch:
        patch = merge(patch, state_patch)
    ack = client.request(dict({"type": "set"}, **patch))
    if ack.get("type") != "ack":
        raise CheckFailed(f"set: {ack}")
    return opened


def merge(a, b):
    out = dict(a)
    for key, value in b.items():
        out[key] = merge(out[key], value) if isinstance(value, dict) and key in out else value
    return out


def test_routing(cluster):
    print("routing: every session of a volume on one replica, the volume read once", flush=True)
    volume = VOLUMES[0]
    before = sum(cluster.loads().values())
    builds_before = cluster.total("penumbra_light_buffer_builds_total")
    clients = [Client(cluster.url(volume)) for _ in range(3)]
    for client in clients:
        open_session(client, volume)
        client.frame()
    holder = cluster.holder_of_sessions(3)
    check(sum(cluster.loads().values()) - before == 1,
          f"{volume} read once in the cluster (loads per replica: {cluster.loads()})")
    builds = cluster.total("penumbra_light_buffer_builds_total") - builds_before
    check(builds == 1, f"its light buffer built once in the cluster for three sessions ({builds})")
    # A client that switches volume reconnects with the new volume in its URL.
    other = VOLUMES[1]
    switcher = Client(cluster.url(other))
    open_session(switcher, other)
    switcher.frame()
    again = Client(cluster.url(other))
    open_session(again, other)
    check(sum(cluster.loads().values()) - before == 2,
          f"a second volume read once more, whichever replica holds it ({cluster.loads()})")
    for client in clients + [switcher, again]:
        client.close()
    time.sleep(0.3)
    return holder


def test_join_link(cluster):
    print("join: a link through the proxy reaches the owner's replica and its frames", flush=True)
    volume = VOLUMES[2]
    owner = Client(cluster.url(volume))
    opened = open_session(owner, volume)
    session = opened["session"]
    viewer = Client(cluster.url(volume, session=session))
    joined = viewer.request({"type": "join", "session": session})
    check(joined.get("type") == "joined" and joined["session"] == session,
          "the viewer joined the owner's session through the proxy")
    owner.frame()
    frame = viewer.any_frame()
    check(frame["frame"]["session"] == session and frame["image_bytes"] > 0,
          "the viewer got the session's frame")
    owner.close()
    viewer.close()
    time.sleep(0.3)


def test_access(cluster):
    print("access: token and Origin checked on the upgrade; wss:// through the proxy", flush=True)
    volume = VOLUMES[0]
    for url, options, status, what in [
            (cluster.url(volume, token=None), {}, 401, "no token"),
            (cluster.url(volume, token="wrong"), {}, 401, "a wrong token"),
            (cluster.url(volume), {"origin": "https://evil.example"}, 403, "a foreign Origin")]:
        try:
            Client(url, **options).close()
            raise CheckFailed(f"{what} was let in")
        except websocket.WebSocketBadStatusException as refused:
            check(refused.status_code == status, f"{what} refused with {status}")
    # The replica itself checks, not only what stands in front of it.
    direct = f"ws://127.0.0.1:{cluster.replicas[0].port}/ws"
    try:
        Client(direct).close()
        raise CheckFailed("a replica let in a client without token")
    except websocket.WebSocketBadStatusException as refused:
        check(refused.status_code == 401, "a replica asked directly refuses a missing token")
    check(metrics(cluster.replicas[0].port).get("penumbra_upgrades_refused_total", 0) >= 1,
          "and counts the refusal in /metrics")
    # Re-creating a session needs a token that the cluster secret proves; nothing is loaded else.
    claimant = Client(cluster.url(VOLUMES[3]))
    loads = sum(cluster.loads().values())
    forged = claimant.request({"type": "resume", "session": "5e551011" * 4,
                               "owner_token": "0" * 32, "volume": VOLUMES[3]})
    check(forged.get("code") == "unknown_session" and sum(cluster.loads().values()) == loads,
          "a resume with a forged token re-creates nothing and loads nothing")
    claimant.close()
    listed = Client(cluster.url(volume), origin="https://app.example")
    check(listed.request({"type": "list_volumes"})["type"] == "volumes",
          "a page from an origin in --allowed-origins is let in")
    listed.close()
    cert = os.path.join(cluster.tls, "tls.crt")
    check(os.path.exists(cert), "nginx's entry point made a self-signed certificate")
    secure = Client(cluster.url(volume, tls=True), sslopt={"ca_certs": cert})
    open_session(secure, volume)
    frame = secure.frame()
    check(frame["image_bytes"] > 0, "wss:// through the proxy, certificate verified: a frame")
    secure.close()
    try:
        Client(cluster.url(volume, tls=True), sslopt={"cert_reqs": ssl.CERT_REQUIRED})
        raise CheckFailed("an unknown certificate was trusted")
    except ssl.SSLError:
        check(True, "a client that does not trust the certificate is refused by TLS")
    time.sleep(0.3)


def test_idle(cluster):
    print("liveness: an idle client outlives the proxy's read timeout", flush=True)
    volume = VOLUMES[0]
    client = Client(cluster.url(volume))
    open_session(client, volume)
    client.frame()
    idle_s = 2 * PROXY_READ_TIMEOUT_S + 1
    time.sleep(idle_s)
    check(not client.closed.is_set(), f"still connected after {idle_s} s idle "
          f"(proxy read timeout {PROXY_READ_TIMEOUT_S} s)")
    check(client.frame(5)["image_bytes"] > 0, "and it gets frames")
    client.close()
    time.sleep(0.3)


def test_unanswered_pings(cluster):
    print("liveness: a client that stops answering pings is dropped; its token resumes",
          flush=True)
    volume = VOLUMES[3]
    owner = Client(cluster.url(volume))
    opened = open_session(owner, volume)
    session, token = opened["session"], opened["owner_token"]
    viewer = Client(cluster.url(volume))
    check(viewer.request({"type": "join", "session": session})["type"] == "joined",
          "a viewer keeps the session")
    resume = {"type": "resume", "session": session, "owner_token": token, "volume": volume}
    successor = Client(cluster.url(volume))
    refused = successor.request(resume)
    check(refused.get("code") == "session_owned", "resume refused while the owner answers")
    owner.freeze()
    dropped_by = time.monotonic() + PING_INTERVAL_S + PING_TIMEOUT_S + 3
    while True:
        answer = successor.request(resume)
        if answer.get("type") == "opened" or time.monotonic() > dropped_by:
            break
        time.sleep(0.2)
    check(answer.get("type") == "opened" and answer["session"] == session
          and not answer.get("recreated"),
          "the silent owner was dropped, and its token resumed the same session")
    successor.frame()
    check(viewer.any_frame()["frame"]["session"] == session, "the viewer watched throughout")
    for client in (owner, viewer, successor):
        client.close()
    time.sleep(0.3)


STATE = {"camera": {"orbit": {"azimuth": 123, "elevation": 20, "distance": 2.2}},
         "light": {"intensity": 2.5, "ambient": 0.3},
         "transfer_function": {"preset": "ct_bone"},
         "settings": {"mode": "dvr"}}


def reconnect(cluster, url, first_message, accept, deadline):
    """Reconnects through the proxy until `first_message` is answered as `accept` wants, as the
    web client does; returns the client and the answer."""
    last = None
    while time.monotonic() < deadline:
        try:
            client = Client(url)
            answer = client.request(first_message, 5)
            if accept(answer):
                return client, answer
            last = answer
            client.close()
        except (OSError, ConnectionError, websocket.WebSocketException, CheckFailed) as e:
            last = e
        time.sleep(0.2)
    raise CheckFailed(f"no {first_message['type']} before the deadline: {last}")


def test_replica_dies(cluster):
    print("failover: kill -9 of a replica; its clients serve frames again with their state",
          flush=True)
    volume = VOLUMES[0]
    owner = Client(cluster.url(volume))
    opened = open_session(owner, volume, STATE)
    session, token = opened["session"], opened["owner_token"]
    viewer = Client(cluster.url(volume, session=session))
    joined = viewer.request({"type": "join", "session": session})
    saved_state = joined["state"]
    owner.frame()
    viewer.any_frame()
    holder = cluster.holder_of_sessions(1)
    holder.kill()
    killed_at = time.monotonic()
    deadline = killed_at + 5.0
    owner.closed.wait(5)
    check(owner.closed.is_set() and viewer.closed.wait(5), "both connections noticed the death")

    results = {}

    def owner_side():
        client, answer = reconnect(
                cluster, cluster.url(volume),
                {"type": "resume", "session": session, "owner_token": token, "volume": volume},
                lambda a: a.get("type") == "opened", deadline)
        if answer.get("recreated"):
            # The new replica has the session under its id, with the default state: send ours.
            # A full state sent back as a `set` restores it (proto/README.md §5).
            ack = client.request(dict({"type": "set"}, **saved_state))
            if ack.get("type") != "ack":
                raise CheckFailed(f"restoring the state: {ack}")
        client.frame(5)
        results["owner"] = (time.monotonic() - killed_at, answer, client)

    def viewer_side():
        client, answer = reconnect(cluster, cluster.url(volume, session=session),
                                   {"type": "join", "session": session},
                                   lambda a: a.get("type") == "joined", deadline)
        # The owner's state arrives with `joined` or, when the viewer came first, as `state`.
        state = answer["state"]
        end = time.monotonic() + 5
        while state != saved_state and time.monotonic() < end:
            state = client.expect(lambda m: m.get("type") == "state", 5)["state"]
        client.frame(5)  # a viewer asks for the current frame, as the web client does
        if answer["volume"]["id"] != volume:
            raise CheckFailed(f"the session came back on {answer['volume']['id']}")
        results["viewer"] = (time.monotonic() - killed_at, state, client)

    def reporting(side, body):
        def run():
            try:
                body()
            except Exception as e:  # said by the check below, with what went wrong
                results[side + " error"] = f"{type(e).__name__}: {e}"
        return run

    threads = [threading.Thread(target=reporting("owner", owner_side)),
               threading.Thread(target=reporting("viewer", viewer_side))]
    for thread in threads:
        thread.start()
    for thread in threads:
        thread.join(20)
    check("owner" in results,
          f"the owner reconnected and resumed its session {results.get('owner error', '')}")
    check("viewer" in results,
          f"the viewer re-joined the same session id {results.get('viewer error', '')}")
    owner_s, answer, new_owner = results["owner"]
    viewer_s, viewer_state, new_viewer = results["viewer"]
    check(answer["session"] == session and answer.get("recreated") is True,
          "another replica re-created the session under its id (the cluster secret proved it)")
    check(owner_s <= 5.0, f"the owner had frames again {owner_s:.2f} s after the kill")
    check(viewer_s <= 5.0, f"the viewer had frames again {viewer_s:.2f} s after the kill")
    check(viewer_state == saved_state,
          "volume, camera, light, transfer function and mode are back as they were")
    cluster.holder_of_sessions(1)
    print(f"reconnect after kill -9: owner {owner_s:.2f} s, viewer {viewer_s:.2f} s", flush=True)
    new_owner.close()
    new_viewer.close()
    return owner_s, viewer_s


def test_browser(cluster):
    print("browser: the web client through nginx over wss://, a replica killed under it",
          flush=True)
    page = (f"https://127.0.0.1:{cluster.https_port}/?"
            + urllib.parse.urlencode({"volume": VOLUMES[1], "token": TOKEN}))
    command = [cluster.args.node, os.path.join(os.path.dirname(__file__), "browser_failover.mjs"),
               "--client", os.path.join(cluster.args.source, "client_web"), "--page", page]
    for replica in cluster.live():
        command += ["--replica", f"{replica.process.pid}:{replica.port}"]
    result = subprocess.run(command, capture_output=True, text=True, timeout=120)
    print(result.stdout + result.stderr, end="", flush=True)
    check(result.returncode == 0, "the web client passed its failover checks")


def run_load(penumbra, port, seconds, token_file):
    command = [penumbra, "load", "--port", str(port), "--clients", "2", "--seconds", str(seconds),
               "--volume", VOLUMES[0], "--mode", "dvr", "--size", "64"]
    if token_file:
        command += ["--token-file", token_file]
    output = subprocess.run(command, capture_output=True, text=True, timeout=seconds + 60)
    if output.returncode != 0:
        raise CheckFailed(f"penumbra load failed: {output.stderr}{output.stdout}")
    for line in output.stdout.splitlines():
        if line.startswith("latency (client)"):
            p50, p95, p99 = (float(x) for x in line.split()[2:5])
            return p50, p99, output.stdout
    raise CheckFailed(f"no latency line in: {output.stdout}")


def measure(cluster, seconds):
    print("measure: penumbra load through nginx and direct, same run", flush=True)
    holder_port = None
    probe = Client(cluster.url(VOLUMES[0]))
    open_session(probe, VOLUMES[0])
    for r in cluster.live():
        if metrics(r.port).get("penumbra_sessions", 0) > 0:
            holder_port = r.port
    probe.close()
    rounds = []
    for _ in range(3):  # interleaved, so that a slow moment of the machine hits both
        rounds.append(("direct", run_load(cluster.args.penumbra, holder_port, seconds,
                                          cluster.token_file)))
        rounds.append(("nginx", run_load(cluster.args.penumbra, cluster.http_port, seconds,
                                         cluster.token_file)))
    for name, (p50, p99, _) in rounds:
        print(f"  {name:7s} p50 {p50:8.2f} ms  p99 {p99:8.2f} ms", flush=True)
    # The proxy's own share, without rendering: round trips of `stats` over one connection.
    direct_url = (f"ws://127.0.0.1:{holder_port}/ws?"
                  + urllib.parse.urlencode({"volume": VOLUMES[0], "token": TOKEN}))
    for name, url in (("direct", direct_url), ("nginx", cluster.url(VOLUMES[0])),
                      ("direct", direct_url), ("nginx", cluster.url(VOLUMES[0]))):
        client = Client(url)
        times = []
        for _ in range(300):
            start = time.perf_counter()
            client.request({"type": "stats"})
            times.append((time.perf_counter() - start) * 1000)
        client.close()
        times.sort()
        print(f"  stats round trip {name:7s} p50 {times[len(times) // 2]:6.3f} ms  "
              f"p99 {times[int(len(times) * 0.99)]:6.3f} ms", flush=True)


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--penumbra", required=True)
    parser.add_argument("--source", required=True)
    parser.add_argument("--work", required=True)
    parser.add_argument("--measure", type=float, default=0)
    parser.add_argument("--node", help="with the built web client: its failover in chromium")
    args = parser.parse_args()
    for tool in ("nginx", "openssl"):
        if shutil.which(tool) is None and not os.path.exists(f"/usr/sbin/{tool}"):
            print(f"{tool} is needed: run scripts/install-deps.sh", file=sys.stderr)
            return 1
    os.environ["PATH"] = os.environ.get("PATH", "") + ":/usr/sbin"
    cluster = Cluster(args)
    status = 0
    try:
        cluster.start()
        test_routing(cluster)
        test_join_link(cluster)
        test_access(cluster)
        test_idle(cluster)
        test_unanswered_pings(cluster)
        if args.measure > 0:
            measure(cluster, args.measure)
        test_replica_dies(cluster)
        if args.node:
            test_browser(cluster)
        print("cluster test passed", flush=True)
    except (CheckFailed, ConnectionError, OSError, websocket.WebSocketException) as e:
        print(f"FAILED: {type(e).__name__}: {e}", flush=True)
        print(f"logs: {cluster.work}", flush=True)
        status = 1
    finally:
        cluster.stop()
    return status


if __name__ == "__main__":
    sys.exit(main())
