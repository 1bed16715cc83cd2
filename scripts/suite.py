#!/usr/bin/env python3
"""The scenario suite (`make suite`): generate scenarios, simulate and evaluate each, summarise.

  scripts/suite.py --tools DIR --output DIR [--count 20] [--seed 1] [--detector default]
                   [--mesh-dir DIR] [--jobs 2] [--keep-bags] [--bags DIR]
                   [--evaluate-args "--params FILE"]

OUTPUT/scenarios/ holds the generated YAMLs and their index (generate_scenarios);
OUTPUT/runs/<name>/ each scenario's report.json, report.md, timeseries.csv and logs (the bag is
deleted once it is scored; --keep-bags keeps it, and a later --keep-bags run replays a kept bag
of the same scenario instead of simulating it again; --bags DIR replays the bags kept in another
suite's output DIR, read-only, and simulates only the scenarios it has no bag of). Then:
  OUTPUT/summary.json  `scenarios` (name, kinds, status, report) and, for every numeric
                       report.json key outside per_object, {median, worst, mean} under the same
                       nested name (worst: the minimum for recall-like keys, else the maximum);
                       `by_kind`: the headline figures per kind of scenario;
                       `objects_by_class`: per class, the object-frame recall and the shares
                       of frames displaced, turned, missed, crossed; `worst_objects`: the ten
                       objects of lowest recall and how their frames failed.
  OUTPUT/summary.md    the same as tables;  OUTPUT/recall.png  per-scenario recall.
Exit status 1 when a scenario failed to simulate or evaluate.
"""
import argparse
import concurrent.futures
import hashlib
import json
import os
import subprocess
import sys
import threading
import time

import yaml

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import suite_summary  # noqa: E402


def run(cmd, log_path):
    with open(log_path, 'w') as log:
        log.write(' '.join(cmd) + '\n')
        log.flush()
        return subprocess.run(cmd, stdout=log, stderr=subprocess.STDOUT).returncode


class Suite:
    def __init__(self, a):
        self.a = a
        self.tools = a.tools
        self.lock = threading.Lock()
        self.done = 0
        self.start = time.time()

    def tool(self, name):
        return os.path.join(self.tools, name)

    def mesh_args(self):
        return ['--mesh-dir', self.a.mesh_dir] if self.a.mesh_dir else []

    def generate(self):
        out = os.path.join(self.a.output, 'scenarios')
        cmd = [self.tool('generate_scenarios'), '--count', str(self.a.count), '--seed',
               str(self.a.seed), '--output', out] + self.mesh_args()
        subprocess.run(cmd, check=True, stdout=subprocess.DEVNULL)
        with open(os.path.join(out, 'scenarios.yaml')) as f:
            index = yaml.safe_load(f)
        for s in index['scenarios']:
            s['path'] = os.path.join(out, s['file'])
        # Every generated scenario is in the same generated building: one map for all.
        self.map = os.path.join(self.a.output, 'static_map.ply')
        self.furniture = os.path.join(self.a.output, 'furniture.yaml')
        subprocess.run([self.tool('write_map'), '--scenario', index['scenarios'][0]['path'],
                        '--mesh', self.map, '--furniture', self.furniture], check=True,
                       stdout=subprocess.DEVNULL)
        return index['scenarios']

    def source(self, s):
        """What a bag was simulated from: the scenario file and the mesh directory."""
        with open(s['path']) as f:
            return hashlib.sha256((f.read() + self.a.mesh_dir).encode()).hexdigest()

    def kept(self, s, bag):
        """Whether bag was kept from simulating this very scenario (its .source says so)."""
        try:
            with open(bag + '.source') as f:
                return os.path.exists(bag) and f.read() == self.source(s)
        except OSError:
            return False

    def shared_bag(self, s):
        """The bag of s that another suite's run kept (--bags), or None."""
        if not self.a.bags:
            return None
        bag = os.path.join(self.a.bags, 'runs', s['name'], 'run.bag')
        return bag if self.kept(s, bag) else None

    def one(self, s):
        d = os.path.join(self.a.output, 'runs', s['name'])
        os.makedirs(d, exist_ok=True)
        own_bag = os.path.join(d, 'run.bag')
        bag = self.shared_bag(s) or own_bag
        entry = {'name': s['name'], 'kinds': s['kinds'], 'index': s, 'status': 'ok'}
        with open(s['path']) as f:
            entry['classes'] = {o['id']: o['class'] for o in yaml.safe_load(f)['objects']}
        t0 = time.time()
        replayed = bag != own_bag or (self.a.keep_bags and self.kept(s, bag))
        if not replayed and run(
                [self.tool('simulate'), '--scenario', s['path'], '--output', bag, '--quiet']
                + self.mesh_args(), os.path.join(d, 'simulate.log')) != 0:
            entry['status'] = 'simulate failed (%s)' % os.path.join(d, 'simulate.log')
        elif self.a.keep_bags and bag == own_bag:
            with open(bag + '.source', 'w') as f:
                f.write(self.source(s))
        t1 = time.time()
        if entry['status'] == 'ok':
            cmd = [self.tool('evaluate'), '--bag', bag, '--output', d, '--scenario', s['path'],
                   '--map', self.map, '--furniture', self.furniture, '--no-plots']
            cmd += self.mesh_args() + (['--detector', self.a.detector] if self.a.detector else [])
            cmd += self.a.evaluate_args.split()
            if run(cmd, os.path.join(d, 'evaluate.log')) != 0:
                entry['status'] = 'evaluate failed (%s)' % os.path.join(d, 'evaluate.log')
        t2 = time.time()
        if not self.a.keep_bags and os.path.exists(own_bag):
            os.remove(own_bag)
        report = os.path.join(d, 'report.json')
        if entry['status'] == 'ok':
            with open(report) as f:
                entry['report'] = json.load(f)
        entry['seconds'] = {'simulate': round(t1 - t0, 1), 'evaluate': round(t2 - t1, 1)}
        self.progress(entry)
        return entry

    def progress(self, e):
        with self.lock:
            self.done += 1
            elapsed = time.time() - self.start
            eta = elapsed / self.done * (self.a.count - self.done)
            line = '[%d/%d] %s' % (self.done, self.a.count, e['name'])
            if 'report' in e:
                o = e['report']['objects']
                line += (': ADD(-S) recall %.3f, ADD-S recall %.3f, %d switches, %d false tracks'
                         % (o['recall_add_or_adds_10'], o['recall_adds_10'], o['identity_switches'],
                            o['false_tracks']))
            else:
                line += ': ' + e['status']
            line += ' (simulate %.0f s, evaluate %.0f s; %.0f s elapsed, ~%.0f s left)' % (
                e['seconds']['simulate'], e['seconds']['evaluate'], elapsed, eta)
            print(line, flush=True)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawTextHelpFormatter)
    ap.add_argument('--tools', required=True)
    ap.add_argument('--output', required=True)
    ap.add_argument('--count', type=int, default=20)
    ap.add_argument('--seed', type=int, default=1)
    ap.add_argument('--detector', default='')
    ap.add_argument('--mesh-dir', default='')
    ap.add_argument('--jobs', type=int, default=2)
    ap.add_argument('--keep-bags', action='store_true')
    ap.add_argument('--bags', default='', help="another suite's output whose kept bags to replay")
    ap.add_argument('--evaluate-args', default='', help='more arguments for evaluate, e.g. "--params FILE"')
    a = ap.parse_args()
    if a.mesh_dir:
        a.mesh_dir = os.path.abspath(a.mesh_dir)
    if a.bags:
        a.bags = os.path.abspath(a.bags)
    os.makedirs(a.output, exist_ok=True)
    suite = Suite(a)
    scenarios = suite.generate()
    hypotheses = 'the detector (%s)' % a.detector if a.detector else 'simulated hypotheses'
    print('suite: %d scenarios (seed %d), %s, %d at a time -> %s'
          % (len(scenarios), a.seed, hypotheses, a.jobs, a.output), flush=True)
    with concurrent.futures.ThreadPoolExecutor(max_workers=max(1, a.jobs)) as pool:
        entries = list(pool.map(suite.one, scenarios))
    summary = suite_summary.summarise(entries, {
        'count': a.count, 'seed': a.seed, 'detector': a.detector, 'mesh_dir': a.mesh_dir,
        'evaluate_args': a.evaluate_args})
    suite_summary.write(summary, a.output)
    print('suite: %s' % suite_summary.headline(summary))
    print('suite: wrote %s' % ', '.join(os.path.join(a.output, f)
                                         for f in ('summary.json', 'summary.md', 'recall.png')))
    return 0 if all(e['status'] == 'ok' for e in entries) else 1


if __name__ == '__main__':
    sys.exit(main())
