#!/usr/bin/env python3
"""The explorer's figures (docs/figures.md "explore" rows), against `shadelab explore` started on
a free port of 127.0.0.1 with a compile store and a Mesa shader cache of its own (temporary
folders: the user's are neither read nor changed):

  1. a method of the table (newton_raphson) at 256x256 on scenes/torus.toml, warm (asked once
     before): the whole panel as the page asks it, the render and the cost streams of float32
     and float16 at once; the time until the last of them ends;
  2. an edited method never compiled (a fresh comment in its source): check, then the render and
     both cost streams at once; the time to the render, to the first family's line and to the
     end of everything;
  3. 50 edits in a row (each a new source: check, render, both cost streams), and the resident
     memory of the server alone and of the server with its workers before and after.

Each step prints its wall time and the load average before it (the machine is shared: state
the load with the figure). Usage: scripts/explore_bench.py [--edits N]   (builds the release
binary first)
"""
import json
import os
import subprocess
import sys
import tempfile
import threading
import time
import urllib.request

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
EDITS = int(sys.argv[sys.argv.index("--edits") + 1]) if "--edits" in sys.argv else 50


def load():
    with open("/proc/loadavg") as f:
        return " ".join(f.read().split()[:3])


def rss_kib(pid):
    try:
        with open(f"/proc/{pid}/status") as f:
            for line in f:
                if line.startswith("VmRSS:"):
                    return int(line.split()[1])
    except OSError:
        pass
    return 0


def children(pid):
    out = subprocess.run(["ps", "-o", "pid=", "--ppid", str(pid)], capture_output=True, text=True)
    return [int(p) for p in out.stdout.split()]


class Client:
    def __init__(self, base, token):
        self.base, self.token = base, token

    def request(self, path, body, on_line=None):
        req = urllib.request.Request(
            self.base + path,
            data=json.dumps(body).encode(),
            headers={"X-Shadelab-Token": self.token, "Content-Type": "application/json"},
        )
        with urllib.request.urlopen(req, timeout=300) as r:
            if on_line is None:
                return json.loads(r.read())
            lines = []
            for raw in r:
                line = json.loads(raw)
                on_line(line)
                lines.append(line)
            return lines


def panel(client, method, seq):
    """The page's requests for one method at once: (render reply, seconds to it, seconds to
    the first family line, seconds to the end of everything, cost lines)."""
    start = time.monotonic()
    marks = {}
    results = {}

    def first_line(line):
        if "family" in line and "first" not in marks:
            marks["first"] = time.monotonic() - start

    def render():
        results["render"] = client.request(
            "/api/v1/render",
            {"method": method, "scene": {"scene": "torus"}, "size": 256, "precision": "f32",
             "budget": "1/255", "tab": "bench", "seq": seq},
        )
        marks["render"] = time.monotonic() - start

    def cost(precision):
        results[precision] = client.request(
            "/api/v1/cost",
            {"method": method, "precision": precision, "tab": "bench-" + precision, "seq": seq},
            first_line,
        )

    threads = [threading.Thread(target=render)] + [
        threading.Thread(target=cost, args=(p,)) for p in ("f32", "f16")
    ]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    end = time.monotonic() - start
    for p in ("f32", "f16"):
        last = results[p][-1]
        assert last.get("done") is True, last
    stats = results["render"]["statistics"]
    assert stats["max_abs_error"] is not None, results["render"]
    return marks["render"], marks.get("first", end), end, results


def edit_source(n):
    return (
        f"// edit {n} {time.time_ns()}\n// shadelab-inputs: interpolated_normal\n"
        "real3 methodNormal() {\n    real3 n = R3(vNormal);\n    real z = dot(n, n);\n"
        "    real y = R(0.5) * (R(3.0) - z);\n    y = y * (R(1.5) - R(0.5) * z * y * y);\n"
        "    return n * y;\n}\n"
    )


def main():
    subprocess.run(["cargo", "build", "--release", "--locked", "--quiet"], cwd=ROOT, check=True)
    work = tempfile.mkdtemp()
    env = dict(os.environ, SHADELAB_STORE=f"{work}/store", MESA_SHADER_CACHE_DIR=f"{work}/mesa")
    server = subprocess.Popen(
        [f"{ROOT}/target/release/shadelab", "explore", "-q"], cwd=ROOT, env=env,
        stdout=subprocess.PIPE, text=True,
    )
    try:
        url = server.stdout.readline().strip()
        base, token = url.split("/?token=")
        client = Client(base, token)
        with open("/proc/cpuinfo") as f:
            model = next(l for l in f if l.startswith("model name")).split(":")[1].strip()
        print(f"machine: {os.cpu_count()} cores, {model}")

        table = {"name": "newton_raphson"}
        panel(client, table, 1)  # cold: compiles, starts the workers
        before = load()
        render_s, first_s, end_s, r = panel(client, table, 2)
        n = sum(1 for l in r["f32"] if "family" in l)
        print(f"table-method-warm: whole panel {end_s * 1e3:.0f} ms (render {render_s * 1e3:.0f} ms, "
              f"{n} families x 2 precisions) (load before: {before})")

        before = load()
        t = time.monotonic()
        check = client.request("/api/v1/check", {"method": {"source": edit_source(0)}})
        check_s = time.monotonic() - t
        assert check["ok"], check
        render_s, first_s, end_s, _ = panel(client, {"source": edit_source(0)}, 3)
        print(f"edited-method-new: check {check_s * 1e3:.0f} ms, then render {render_s * 1e3:.0f} ms, "
              f"first family {first_s * 1e3:.0f} ms, everything {end_s * 1e3:.0f} ms "
              f"(load before: {before})")

        def memory():
            kids = children(server.pid)
            return rss_kib(server.pid), rss_kib(server.pid) + sum(rss_kib(k) for k in kids)

        own0, all0 = memory()
        before = load()
        t = time.monotonic()
        for i in range(EDITS):
            src = edit_source(i + 1)
            assert client.request("/api/v1/check", {"method": {"source": src}})["ok"]
            panel(client, {"source": src}, 10 + i)
        own1, all1 = memory()
        print(f"edits-memory: {EDITS} edits in {time.monotonic() - t:.1f} s; server "
              f"{own0 / 1024:.0f} -> {own1 / 1024:.0f} MiB, with its workers "
              f"{all0 / 1024:.0f} -> {all1 / 1024:.0f} MiB (load before: {before})")
    finally:
        server.terminate()
        server.wait(timeout=30)
        subprocess.run(["rm", "-rf", work])


if __name__ == "__main__":
    main()
