#!/usr/bin/env python3
"""Reference driver for hdm's device bridge (docs/bridge.md), Python standard library only.

Plays a recorded trajectory (the CSV of `hdm sculpt --forces` / `hdm feel --replay`: columns
time_s, device_x_m, device_y_m, device_z_m, optionally tool_on and the handle's orientation
device_qw, device_qx, device_qy, device_qz) into hdm as device packets over UDP on localhost or
POSIX shared memory, at a chosen rate, and records the force packets it gets back: the force, the
surface contact point and the torque about the handle's tip (zero unless hdm's device spec allows
a torque, docs/bridge.md). A vendor driver does the same with its device's readings instead of the
file's rows.

    python3 bridge_client.py --udp 47000 trajectory.csv --rate 1000 --forces forces.csv --secret-file s.key
    HDM_BRIDGE_SECRET=... python3 bridge_client.py --shm hdm-bridge trajectory.csv --lockstep

It first opens a session: a hello packet with the shared secret (the file hdm was given with
--secret-file, or the HDM_BRIDGE_SECRET environment variable) and a fresh random session id, sent
again every 5 ms until hdm answers with a force packet of that session; every packet then carries
the id, and the sequence numbers start at 1 again (a restarted client is a new session).

--lockstep waits for the force that answers each packet before sending the next (one servo tick
per row, as a replay; the tests use it); otherwise rows go out on the rate's clock and the newest
force is kept. A summary (packets, forces, round trip median and p99 in µs, the largest force and
torque received) is printed as JSON.
"""
import argparse
import json
import math
import mmap
import os
import select
import socket
import struct
import sys
import time

MAGIC, VERSION, DEVICE, FORCE, HELLO, SIZE = 0x424D4448, 3, 1, 2, 3, 152  # docs/bridge.md
# magic version kind size flags sequence session time position velocity buttons 0 orientation(w x y z) angular
DEVICE_FMT = "<IHHIIQQd3d3dII4d3d"
FORCE_FMT = "<IHHIIQQQ3d3dd3d32x"  # magic version kind size flags sequence session tick force contact gain torque
HELLO_FMT = "<IHHIIQQI56sI56x"  # magic version kind size flags sequence(0) session secret_bytes secret reserved
DEVICE_END, FORCE_CONTACT, FORCE_WATCHDOG = 1, 1, 2
REGION_MAGIC, DEVICE_BLOCK, FORCE_BLOCK = 0x524D4448, 64, 256
MIN_SECRET, MAX_SECRET = 16, 56
assert struct.calcsize(DEVICE_FMT) == SIZE and struct.calcsize(FORCE_FMT) == SIZE and struct.calcsize(HELLO_FMT) == SIZE
SESSION = 0  # this run's session id, drawn in main()


def device_packet(seq, t, pos, vel, buttons, flags=0, orientation=(1.0, 0.0, 0.0, 0.0), angular=(0.0, 0.0, 0.0)):
    return struct.pack(
        DEVICE_FMT, MAGIC, VERSION, DEVICE, SIZE, flags, seq, SESSION, t, *pos, *vel, buttons, 0, *orientation, *angular
    )


def hello_packet(secret):
    return struct.pack(HELLO_FMT, MAGIC, VERSION, HELLO, SIZE, 0, 0, SESSION, len(secret), secret, 0)


def decode_force(data):
    """A force packet of this run's session as a dict, or None when it is not one."""
    if len(data) != SIZE:
        return None
    f = struct.unpack(FORCE_FMT, data)
    if f[0] != MAGIC or f[1] != VERSION or f[2] != FORCE or f[3] != SIZE or f[6] != SESSION:
        return None
    if not all(math.isfinite(x) for x in f[8:18]):
        return None
    return {
        "flags": f[4],
        "sequence": f[5],
        "tick": f[7],
        "force": f[8:11],
        "contact": f[11:14],
        "gain": f[14],
        "torque": f[15:18],
    }


def read_secret(path, wait_s=5.0):
    """The shared secret: the file's content (hdm creates it, mode 0600) or HDM_BRIDGE_SECRET."""
    if path is None:
        s = os.environ.get("HDM_BRIDGE_SECRET")
        if s is None:
            sys.exit("the bridge needs its shared secret: --secret-file FILE or HDM_BRIDGE_SECRET")
        secret = s.encode()
    else:
        deadline = time.monotonic() + wait_s
        while not os.path.exists(path):  # hdm may still be creating it
            if time.monotonic() > deadline:
                sys.exit(f"{path}: no such secret file (is hdm listening?)")
            time.sleep(0.01)
        st = os.stat(path, follow_symlinks=False)
        if st.st_mode & 0o077:
            sys.exit(f"{path}: the secret is readable by others (mode {st.st_mode & 0o777:03o}); chmod 600 it")
        with open(path, "rb") as f:
            secret = f.read()
    secret = secret.rstrip(b" \t\r\n")
    if not MIN_SECRET <= len(secret) <= MAX_SECRET:
        sys.exit(f"the bridge secret has {len(secret)} bytes; it needs {MIN_SECRET} to {MAX_SECRET}")
    return secret


def open_session(link, secret, wait_s):
    """Sends the hello every 5 ms until hdm answers with a force packet of this session; returns
    the time from the first hello to the answer [s]."""
    start = time.monotonic()
    deadline = start + wait_s
    while time.monotonic() < deadline:
        link.send(hello_packet(secret))
        if link.force(0.005) is not None:
            return time.monotonic() - start
    sys.exit(f"hdm did not answer the hello within {wait_s} s (is it listening, with the same secret?)")


def quaternion_log(q):
    """The rotation vector (axis times angle [rad]) of the unit quaternion q = (w, x, y, z)."""
    w, v = q[0], q[1:]
    if w < 0:
        w, v = -w, tuple(-c for c in v)
    s = math.sqrt(sum(c * c for c in v))
    return (0.0, 0.0, 0.0) if s == 0 else tuple(2 * math.atan2(s, w) / s * c for c in v)


def quaternion_mul(a, b):
    aw, ax, ay, az = a
    bw, bx, by, bz = b
    return (aw * bw - ax * bx - ay * by - az * bz, aw * bx + ax * bw + ay * bz - az * by,
            aw * by - ax * bz + ay * bw + az * bx, aw * bz + ax * by - ay * bx + az * bw)


def read_trajectory(path):
    """Rows (time, position, velocity, buttons, orientation, angular velocity) of a replay CSV;
    velocities as hdm's ReplayDevice makes them (backward differences; the angular one from the
    turn between rows), the orientation normalised and the identity without its columns."""
    with open(path) as f:
        header = [c.strip() for c in f.readline().split(",")]
        try:
            it, ix, iy, iz = (header.index(c) for c in ("time_s", "device_x_m", "device_y_m", "device_z_m"))
        except ValueError:
            sys.exit(f"{path}: the header lacks time_s, device_x_m, device_y_m or device_z_m")
        ib = header.index("tool_on") if "tool_on" in header else None
        qcols = ("device_qw", "device_qx", "device_qy", "device_qz")
        iq = [header.index(c) for c in qcols if c in header]
        if len(iq) not in (0, 4):
            sys.exit(f"{path}: the orientation columns device_qw,device_qx,device_qy,device_qz come all four or none")
        rows = []
        for n, line in enumerate(f, start=2):
            if not line.strip():
                continue
            c = line.split(",")
            try:
                t, p = float(c[it]), (float(c[ix]), float(c[iy]), float(c[iz]))
                b = int(c[ib]) if ib is not None else 0
                q = tuple(float(c[k]) for k in iq) if iq else (1.0, 0.0, 0.0, 0.0)
            except (ValueError, IndexError):
                sys.exit(f"{path}:{n}: malformed row")
            norm = math.sqrt(sum(x * x for x in q))
            if not (math.isfinite(norm) and norm > 0):
                sys.exit(f"{path}:{n}: the orientation is not a finite, non-zero quaternion")
            rows.append((t, p, b, tuple(x / norm for x in q)))
    out = []
    for k, (t, p, b, q) in enumerate(rows):
        dt = t - rows[k - 1][0] if k > 0 else 0.0
        v = tuple((p[i] - rows[k - 1][1][i]) / dt for i in range(3)) if dt > 0 else (0.0, 0.0, 0.0)
        prev = rows[k - 1][3] if k > 0 else q
        turn = quaternion_log(quaternion_mul(q, (prev[0], -prev[1], -prev[2], -prev[3])))
        w = tuple(c / dt for c in turn) if dt > 0 else (0.0, 0.0, 0.0)
        out.append((t, p, v, b, q, w))
    return out


class Udp:
    def __init__(self, port):
        self.s = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
        self.s.connect(("127.0.0.1", port))
        self.s.setblocking(False)

    def send(self, data):
        try:
            self.s.send(data)
        except (ConnectionRefusedError, BlockingIOError):
            pass  # nobody listening yet, or the socket buffer is full: this packet is lost, as UDP may

    def force(self, timeout):
        """The newest force packet that arrived (waiting up to timeout seconds for one), or None."""
        newest = None
        while True:
            try:
                newest = decode_force(self.s.recv(256)) or newest
                continue
            except (BlockingIOError, ConnectionRefusedError):
                pass
            if newest is not None or timeout <= 0:
                return newest
            ready, _, _ = select.select([self.s], [], [], timeout)
            if not ready:
                return None
            timeout = 0


class Shm:
    def __init__(self, name, wait_s=5.0):
        path, deadline = "/dev/shm/" + name, time.monotonic() + wait_s
        while True:
            try:
                fd = os.open(path, os.O_RDWR)
                break
            except FileNotFoundError:
                if time.monotonic() > deadline:
                    sys.exit(f"shm:{name}: no such region (is hdm listening?)")
                time.sleep(0.01)
        self.m = mmap.mmap(fd, 4096)
        os.close(fd)
        # The blocks' sequence words as aligned 64-bit words: one load or store each (struct would
        # write them byte by byte, and a reader could see a half-carried word).
        self.words = memoryview(self.m).cast("Q")
        self.dev_word, self.force_word = DEVICE_BLOCK // 8, FORCE_BLOCK // 8
        while struct.unpack_from("<I", self.m, 0)[0] != REGION_MAGIC:
            if time.monotonic() > deadline:
                sys.exit(f"shm:{name}: the region has no bridge header")
            time.sleep(0.001)

    def send(self, data):
        # Seqlock writer: odd while writing, even again after (x86-64 keeps stores in order).
        c = self.words[self.dev_word]
        self.words[self.dev_word] = c + 1
        self.m[DEVICE_BLOCK + 8 : DEVICE_BLOCK + 8 + SIZE] = data
        self.words[self.dev_word] = c + 2

    def force(self, timeout):
        deadline = time.perf_counter() + timeout
        while True:
            c1 = self.words[self.force_word]
            data = self.m[FORCE_BLOCK + 8 : FORCE_BLOCK + 8 + SIZE]
            c2 = self.words[self.force_word]
            if c1 == c2 and c1 % 2 == 0 and c1 > 0:
                f = decode_force(data)
                if f is not None:
                    return f
            if time.perf_counter() >= deadline:
                return None


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    g = ap.add_mutually_exclusive_group(required=True)
    g.add_argument("--udp", type=int, metavar="PORT", help="hdm's bridge on udp:PORT (127.0.0.1)")
    g.add_argument("--shm", metavar="NAME", help="hdm's bridge on shm:NAME (/dev/shm/NAME)")
    ap.add_argument("csv", help="trajectory (time_s, device_x_m, device_y_m, device_z_m[, tool_on])")
    ap.add_argument("--rate", type=float, default=1000.0, help="packets per second [Hz] (default 1000)")
    ap.add_argument("--lockstep", action="store_true", help="wait for each packet's force before the next")
    ap.add_argument("--timeout", type=float, default=2.0, help="lockstep: give up on a force after this [s]")
    ap.add_argument("--forces", help="write the forces received, one row per packet sent, to this CSV")
    ap.add_argument("--stop-after", type=int, default=0, help="send only this many rows, then go silent")
    ap.add_argument("--no-end", action="store_true", help="do not send the end packet")
    ap.add_argument("--secret-file", help="the bridge's shared secret (default: HDM_BRIDGE_SECRET)")
    ap.add_argument("--connect-timeout", type=float, default=5.0, help="wait this long for hdm's answer [s]")
    a = ap.parse_args()
    if not (a.rate > 0):
        sys.exit("--rate must be positive")
    global SESSION
    while SESSION == 0:
        SESSION = struct.unpack("<Q", os.urandom(8))[0]
    secret = read_secret(a.secret_file, a.connect_timeout)

    rows = read_trajectory(a.csv)
    if a.stop_after > 0:
        rows = rows[: a.stop_after]
    link = Udp(a.udp) if a.udp is not None else Shm(a.shm)
    session_s = open_session(link, secret, a.connect_timeout)
    period, start = 1.0 / a.rate, time.perf_counter()
    sent_at, rtt, records, lost = {}, [], [], 0
    last = None

    def take(f):  # a force packet received: the newest, and the round trip of the packet it answers
        nonlocal last
        if f is not None:
            if f["sequence"] in sent_at:
                rtt.append(time.perf_counter() - sent_at.pop(f["sequence"]))
            last = f

    for k, (t, p, v, b, q, w) in enumerate(rows):
        seq = k + 1
        if not a.lockstep:
            while time.perf_counter() < start + k * period:
                take(link.force(0))  # forces come while waiting for the next row's time
        sent_at[seq] = time.perf_counter()
        link.send(device_packet(seq, t, p, v, b, orientation=q, angular=w))
        if a.lockstep:
            deadline = sent_at[seq] + a.timeout
            f = None
            while time.perf_counter() < deadline:
                f = link.force(deadline - time.perf_counter())
                if f is not None and f["sequence"] >= seq:
                    break
            if f is None or f["sequence"] < seq:
                lost += 1  # hdm is gone (or stopped answering): stop rather than wait per row
                records.append((seq, t, last))
                break
            take(f)
        else:
            take(link.force(0))
        records.append((seq, t, last))
    if not a.no_end and rows:
        link.send(device_packet(len(rows) + 1, rows[-1][0], rows[-1][1], (0.0, 0.0, 0.0), 0, DEVICE_END,
                                orientation=rows[-1][4]))

    if a.forces:
        with open(a.forces + ".tmp", "w") as f:
            f.write("sequence,time_s,force_x_n,force_y_n,force_z_n,contact,watchdog,gain,answered_sequence,tick,"
                    "contact_x_m,contact_y_m,contact_z_m,torque_x_nm,torque_y_nm,torque_z_nm\n")
            for seq, t, r in records:
                if r is None:
                    f.write(f"{seq},{t!r},0,0,0,0,0,0,0,0,0,0,0,0,0,0\n")
                else:
                    fx, fy, fz = r["force"]
                    cx, cy, cz = r["contact"]
                    tx, ty, tz = r["torque"]
                    f.write(f"{seq},{t!r},{fx!r},{fy!r},{fz!r},{r['flags'] & FORCE_CONTACT},"
                            f"{(r['flags'] & FORCE_WATCHDOG) >> 1},{r['gain']!r},{r['sequence']},{r['tick']},"
                            f"{cx!r},{cy!r},{cz!r},{tx!r},{ty!r},{tz!r}\n")
        os.replace(a.forces + ".tmp", a.forces)
    rtt_us = sorted(x * 1e6 for x in rtt)
    summary = {"packets": len(rows), "answered": len(rtt_us), "lost": lost, "session_ms": session_s * 1e3,
               "rtt_median_us": rtt_us[len(rtt_us) // 2] if rtt_us else None,
               "rtt_p99_us": rtt_us[min(len(rtt_us) - 1, int(0.99 * len(rtt_us)))] if rtt_us else None,
               "max_force_n": max((math.hypot(*r["force"]) for _, _, r in records if r), default=0.0),
               "max_torque_nm": max((math.hypot(*r["torque"]) for _, _, r in records if r), default=0.0)}
    print(json.dumps(summary))
    return 1 if a.lockstep and lost else 0


if __name__ == "__main__":
    sys.exit(main())
