#!/usr/bin/env python3
"""make soak: the demo bag in a loop at 3x through tracker + detector + semap_bridge.

Usage: soak.py --tools DIR --bag BAG --output DIR [--minutes 30] [--rate 3] [--period 10]

Starts a SEMAP database (scripts/semap-db.sh, in OUTPUT/db) and a roscore of its own, then
replay.launch (loop, no rviz, semap; the bag plays once the tracker has subscribed). Every PERIOD
s it samples each node's RSS, open file descriptors and threads (/proc), the nodes' counters on
/diagnostics (frames, tracks, frame time, the bridge's queue and rows) and the database size.
Writes OUTPUT/soak.json:
  {minutes, samples: [...], rss_growth_after_warmup: {node: fraction}, rss_peak_growth: {...},
   fds_growth: {node: n}, crashes, frames_in, frames_out, dropped_counted, frames_published,
   dropped_uncounted, probe_missed, db_rows_expected, db_rows_found}
rss_growth_after_warmup compares the median RSS of the last WINDOW_S of the run with that of the
first WINDOW_S after the warm-up: what the node keeps, not the images it holds at one instant
(its input queues fill and drain, and freed image buffers go back to the system). A leak shows
there as it does in single samples. rss_peak_growth is the largest sample after the warm-up
against that first window's median. rss_anon_growth_after_warmup is the same for the anonymous
part of the RSS (heap, stacks; /proc RssAnon), without the mapped code and data of the libraries.
The tracker's diagnostics in each sample carry the allocator's own view (heap_in_use_mb,
heap_free_held_mb): a growing in-use figure is a leak, a growing free-held one is fragmentation.
frames_published counts the depth images the player sent, from the header.seq this script's own
subscriber sees (it reads nothing else): every loop of the bag (whose images are numbered without
gaps) it saw restart plus the current one up to the last seq seen; for another bag, the images
seen and the gaps between them (probe_missed, the probe's own losses). frames_in counts those that
reached the tracker's frame callback, frames_out those it processed. dropped_counted is every
depth image the tracker knows it lost:
- those it received and dropped with a count (duplicates, out of order, skipped, failed);
- those that never reached its frame callback (depth_received - frames_in): superseded in its
  input buffer while it was behind, or never matched by the camera_info synchronisation;
- those lost before it (depth_lost_before, from gaps in header.seq).
dropped_uncounted = frames_published - frames_out - dropped_counted, which should be 0 (below 0,
images were counted twice). At the end the bag is paused and the counters are read once the
bridge has written its backlog. Exit status 1 when a node crashed, our nodes' RSS grew by 5 % or
more after the warm-up (2 min), a dropped image was not counted, or the database rows differ from
the rows the bridge wrote.
"""
import argparse
import json
import os
import signal
import statistics
import socket
import struct
import subprocess
import sys
import threading
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
NODES = {  # name in soak.json -> what its command line holds
    "tracker_manager": "__name:=scene_graph_tracker_manager",
    "semap_bridge": "semap_bridge_node",
    "player": "__name:=player",
}
OURS = ("tracker_manager", "semap_bridge")  # the RSS goal; rosbag play's buffer varies by design
WARMUP_S = 120.0
WINDOW_S = 120.0


def free_port():
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def parent(pid):
    with open("/proc/%d/stat" % pid) as f:
        return int(f.read().rsplit(")", 1)[1].split()[1])


def descends(pid, ancestor):
    while pid > 1:
        if pid == ancestor:
            return True
        pid = parent(pid)
    return False


def pids(launch_pid):
    """name -> pid of each soaked process that runs now below the launch (another launch of the
    same nodes on this machine is not ours)."""
    found = {}
    for p in os.listdir("/proc"):
        if not p.isdigit():
            continue
        try:
            if not descends(int(p), launch_pid):
                continue
            with open("/proc/%s/cmdline" % p, "rb") as f:
                cmd = f.read().replace(b"\0", b" ").decode(errors="replace")
        except (OSError, ValueError, IndexError):
            continue
        for name, marker in NODES.items():
            if marker in cmd and "roslaunch" not in cmd:
                found[name] = int(p)
    return found


def proc_sample(pid):
    out = {}
    try:
        with open("/proc/%d/status" % pid) as f:
            for line in f:
                if line.startswith("VmRSS:"):
                    out["rss_mb"] = int(line.split()[1]) / 1024.0
                elif line.startswith("RssAnon:"):  # heap and stacks; RssFile is mapped code
                    out["rss_anon_mb"] = int(line.split()[1]) / 1024.0
                elif line.startswith("Threads:"):
                    out["threads"] = int(line.split()[1])
        out["fds"] = len(os.listdir("/proc/%d/fd" % pid))
    except OSError:
        return None
    return out


class Listener:
    """The latest /diagnostics values per status name, and the depth images published."""

    def __init__(self, depth_topic):
        import rospy
        from diagnostic_msgs.msg import DiagnosticArray
        rospy.init_node("soak_probe", anonymous=True, disable_signals=True)
        self.lock = threading.Lock()
        self.status = {}
        self.depth_images = 0
        self.missed = 0  # gaps in header.seq of the images this probe saw: its own losses
        self.last_seq = None
        self.restarts = 0  # seq stepped back: the bag looped
        rospy.Subscriber("/diagnostics", DiagnosticArray, self.on_diagnostics, queue_size=50)
        # Undecoded (AnyMsg): the probe only reads header.seq, so it keeps up with the player.
        rospy.Subscriber(depth_topic, rospy.AnyMsg, self.on_depth, queue_size=1000,
                         buff_size=2 ** 27)

    def on_diagnostics(self, msg):
        with self.lock:
            for s in msg.status:
                values = {}
                for kv in s.values:
                    try:
                        values[kv.key] = float(kv.value)
                    except ValueError:
                        values[kv.key] = kv.value
                self.status[s.name] = values

    def on_depth(self, msg):
        seq = struct.unpack_from("<I", msg._buff, 0)[0]  # a Header comes first: seq, stamp, frame
        with self.lock:
            self.depth_images += 1
            if self.last_seq is not None and seq > self.last_seq + 1:
                self.missed += seq - self.last_seq - 1
            self.restarts += self.last_seq is not None and seq < self.last_seq
            self.last_seq = seq

    def snapshot(self, bag_seqs=None):
        """(diagnostics, images published). With the bag's (first, last) depth seq: every loop the
        probe saw restart, and the current one up to the last seq seen (rosbag play drops
        nothing); else those seen and the gaps between them."""
        with self.lock:
            status = {k: dict(v) for k, v in self.status.items()}
            if bag_seqs and self.last_seq is not None:
                first, last = bag_seqs
                return status, self.restarts * (last - first + 1) + self.last_seq - first + 1
            return status, self.depth_images + self.missed


def db_query(db_dir, port, sql):
    env = dict(os.environ, PGPASSFILE=os.path.join(db_dir, "bridge.pgpass"))
    r = subprocess.run(["psql", "-X", "-qtA", "-h", "127.0.0.1", "-p", str(port), "-U",
                        "semap_bridge", "-d", "semap", "-c", sql], env=env, capture_output=True,
                       text=True, timeout=60)
    return r.stdout.strip() if r.returncode == 0 else None


def growth(samples, node, key, relative, peak=False):
    """Median of the last WINDOW_S against the median of the first WINDOW_S after the warm-up
    (peak: the largest sample after the warm-up against the latter); relative or absolute."""
    series = [(s["t"], s["nodes"][node][key]) for s in samples if node in s["nodes"]]
    after = [(t, v) for t, v in series if t >= WARMUP_S]
    if len(after) < 2:
        return None
    first = statistics.median(v for t, v in after if t < after[0][0] + WINDOW_S)
    last = max(v for t, v in after) if peak else \
        statistics.median(v for t, v in after if t > after[-1][0] - WINDOW_S)
    return (last - first) / first if relative else last - first


def bag_seqs(bag, topic):
    """(first, last) header.seq of the bag's depth images when they are numbered without gaps;
    None otherwise."""
    import rosbag
    seqs = []
    with rosbag.Bag(bag) as b:
        for _, raw, _ in b.read_messages(topics=[topic], raw=True):
            seqs.append(struct.unpack_from("<I", raw[1], 0)[0])
    if seqs and seqs == list(range(seqs[0], seqs[0] + len(seqs))):
        return seqs[0], seqs[-1]
    return None


def drain(listener, env, seqs, limit_s=600.0):
    """Pauses the bag, then waits until the bridge has nothing pending and no counter moves (two
    snapshots 3 s apart alike). Returns the last snapshot."""
    subprocess.run(["rosservice", "call", "/player/pause_playback", "true"], env=env,
                   capture_output=True, timeout=30)
    last, start = None, time.time()
    while True:
        time.sleep(3.0)
        snap = listener.snapshot(seqs)
        pending = snap[0].get("scene_graph_tracker: semap_bridge", {}).get("pending", -1)
        if (pending == 0 and snap == last) or time.time() - start > limit_s:
            if pending != 0:
                print("soak: the bridge still had %s frames pending after %g s" % (pending, limit_s))
            return snap
        last = snap


def play_when_subscribed(depth_topic, env, limit_s=120.0):
    """Unpauses the player once a node besides this probe subscribes to the depth images (the
    tracker is up), so that no image is published before the tracker can count it."""
    import rosgraph
    master = rosgraph.Master("/soak")
    start = time.time()
    while time.time() - start < limit_s:
        subscribers = dict(master.getSystemState()[1]).get(depth_topic, [])
        if [n for n in subscribers if not n.startswith("/soak_probe")]:
            break
        time.sleep(0.5)
    else:
        raise SystemExit("soak: nothing subscribed to %s within %g s" % (depth_topic, limit_s))
    time.sleep(2.0)  # the connections to the player
    subprocess.run(["rosservice", "call", "/player/pause_playback", "false"], env=env,
                   stdout=subprocess.DEVNULL, check=True)


def stop_launch(launch):
    """SIGINT to roslaunch's process group, SIGKILL after 30 s; it may have ended already."""
    try:
        os.killpg(launch.pid, signal.SIGINT)
        launch.wait(timeout=30)
    except ProcessLookupError:
        pass
    except subprocess.TimeoutExpired:
        os.killpg(launch.pid, signal.SIGKILL)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--bag", required=True)
    ap.add_argument("--output", required=True)
    ap.add_argument("--minutes", type=float, default=30.0)
    ap.add_argument("--rate", type=float, default=3.0)
    ap.add_argument("--period", type=float, default=10.0)
    ap.add_argument("--depth-topic", default="/camera/depth_registered/image_raw")
    a = ap.parse_args()
    seqs = bag_seqs(a.bag, a.depth_topic)
    os.makedirs(a.output, exist_ok=True)
    db_dir, db_port, ros_port = os.path.join(os.path.abspath(a.output), "db"), free_port(), free_port()
    env = dict(os.environ, ROS_MASTER_URI="http://localhost:%d" % ros_port)
    os.environ.update(env)
    subprocess.run(["rm", "-rf", db_dir])
    subprocess.run([os.path.join(ROOT, "scripts/semap-db.sh"), "start", db_dir, str(db_port)],
                   check=True, stdout=subprocess.DEVNULL)
    log = open(os.path.join(a.output, "launch.log"), "w")
    launch = subprocess.Popen(
        ["roslaunch", "-p", str(ros_port), "scene_graph_tracker", "replay.launch",
         "bag:=" + os.path.abspath(a.bag), "rviz:=false", "loop:=true", "semap:=true",
         "rate:=%g" % a.rate, "paused:=true", "semap_db_dir:=" + db_dir, "semap_db_port:=%d" % db_port],
        stdout=log, stderr=subprocess.STDOUT, env=env, start_new_session=True)
    samples, crashes, seen = [], 0, {}
    try:
        for _ in range(100):
            if launch.poll() is not None:
                raise SystemExit("soak: roslaunch ended (see %s)" % log.name)
            if subprocess.run(["rosparam", "get", "/use_sim_time"], capture_output=True,
                              env=env).returncode == 0:
                break
            time.sleep(0.2)
        listener = Listener(a.depth_topic)
        play_when_subscribed(a.depth_topic, env)
        start = time.time()
        while time.time() - start < 60.0 * a.minutes:
            time.sleep(a.period)
            if launch.poll() is not None:
                crashes += 1
                print("soak: roslaunch ended (see %s)" % log.name, flush=True)
                break
            t = time.time() - start
            now = pids(launch.pid)
            for name, pid in now.items():
                if name in seen and seen[name] != pid:
                    crashes += 1  # restarted under another pid
                seen[name] = pid
            crashes += sum(1 for name in seen if name not in now)
            status, published = listener.snapshot(seqs)
            tracker = status.get("scene_graph_tracker: tracker", {})
            bridge = status.get("scene_graph_tracker: semap_bridge", {})
            sample = {"t": round(t, 1),
                      "nodes": {n: s for n, s in ((n, proc_sample(p)) for n, p in now.items()) if s},
                      "tracker": tracker, "semap_bridge": bridge,
                      "detector": status.get("scene_graph_tracker: detector", {}),
                      "frames_published": published,
                      "db_bytes": db_query(db_dir, db_port, "SELECT pg_database_size('semap')")}
            samples.append(sample)
            print("[soak %5.1f/%g min] frames %d published, %d processed; %s objects; frame %s ms; "
                  "bridge pending %s; RSS %s" % (
                      t / 60, a.minutes, published, tracker.get("frames_processed", 0),
                      tracker.get("objects", "-"), tracker.get("frame_ms", "-"),
                      bridge.get("pending", "-"),
                      ", ".join("%s %.0f MB" % (n, s["rss_mb"]) for n, s in sample["nodes"].items())),
                  flush=True)
        status, published = drain(listener, env, seqs)
        rows = db_query(db_dir, db_port, "SELECT count(*) FROM pose_history")
    finally:
        stop_launch(launch)
    tracker = status.get("scene_graph_tracker: tracker", {})
    bridge = status.get("scene_graph_tracker: semap_bridge", {})
    subprocess.run([os.path.join(ROOT, "scripts/semap-db.sh"), "stop", db_dir, str(db_port)],
                   stdout=subprocess.DEVNULL)
    frames_in = int(tracker.get("frames_in", 0))
    frames_out = int(tracker.get("frames_processed", 0))
    dropped = sum(int(tracker.get(k, 0)) for k in (
        "frames_skipped", "frames_failed", "duplicate_stamps", "out_of_order", "depth_lost_before"))
    dropped += max(0, int(tracker.get("depth_received", frames_in)) - frames_in)
    report = {
        "minutes": a.minutes, "rate": a.rate, "samples": samples,
        "rss_growth_after_warmup": {n: growth(samples, n, "rss_mb", True) for n in NODES},
        "rss_peak_growth": {n: growth(samples, n, "rss_mb", True, peak=True) for n in NODES},
        "rss_anon_growth_after_warmup": {n: growth(samples, n, "rss_anon_mb", True) for n in NODES},
        "fds_growth": {n: growth(samples, n, "fds", False) for n in NODES},
        "crashes": crashes,
        "frames_published": published, "frames_in": frames_in,
        "frames_out": frames_out, "dropped_counted": dropped,
        "dropped_uncounted": published - frames_out - dropped,  # < 0: counted twice
        "probe_missed": listener.missed,
        "db_rows_expected": int(bridge.get("pose_rows", -1)),
        "db_rows_found": int(rows) if rows and rows.isdigit() else -1,
        "bridge": bridge,
    }
    with open(os.path.join(a.output, "soak.json"), "w") as f:
        json.dump(report, f, indent=1)
    ok = (crashes == 0 and report["db_rows_expected"] == report["db_rows_found"] and
          report["dropped_uncounted"] == 0 and
          all(g is not None and g < 0.05 for n, g in report["rss_growth_after_warmup"].items()
              if n in OURS and a.minutes * 60 > WARMUP_S + 2 * a.period))
    print("soak: %d crashes; frames %d published, %d in, %d out, %d dropped (counted), %d not "
          "counted; database rows %d of %d written; RSS growth after warm-up %s -> %s" % (
              crashes, published, frames_in, report["frames_out"], dropped,
              report["dropped_uncounted"], report["db_rows_found"], report["db_rows_expected"],
              {n: None if g is None else round(g, 4)
               for n, g in report["rss_growth_after_warmup"].items()},
              os.path.join(a.output, "soak.json")))
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
