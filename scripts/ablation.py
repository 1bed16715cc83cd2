#!/usr/bin/env python3
"""Tracker rules judged on the scenario suite (`make ablation`): the suite with every rule of a
variants file switched off (or a candidate switched on), one suite run per variant, all replaying
the same bags.

  scripts/ablation.py --tools DIR --output DIR [--variants config/ablation.yaml] [--only a,b]
                      [--count 20] [--seed 1] [--detector default] [--mesh-dir DIR] [--jobs 2]

OUTPUT/baseline/ is the suite with the package's parameters; it simulates the bags and keeps them
(1.6 GB each), and a later run replays them. OUTPUT/<variant>/ is the suite with the variant's
parameters on top of the defaults (OUTPUT/<variant>/params.yaml, passed to evaluate as --params;
the defaults are config/tracker.yaml's values). Then:
  OUTPUT/ablation.json  per variant: its parameters and the suite's {median, worst, mean} of the
                        headline figures, and per scenario its ADD(-S) recall
  OUTPUT/ablation.md    the table: each variant against the baseline
A variant already scored with the same parameters and bags is read, not run again (--rerun runs
it anyway). Progress goes to stdout, each suite's log to OUTPUT/<variant>/suite.log.
"""
import argparse
import json
import os
import subprocess
import sys
import time

import yaml

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import suite_summary  # noqa: E402

FIGURES = [('objects.recall_add_or_adds_10', 'ADD(-S) recall', ('median', 'worst', 'mean')),
           ('objects.rotation_error_mean_deg', 'rotation (deg)', ('median',)),
           ('objects.identity_switches', 'switches', ('median', 'worst')),
           ('objects.false_tracks', 'false tracks', ('median',)),
           ('relations.recall', 'relation recall', ('median',)),
           ('timing.frame_ms_median', 'frame (ms)', ('median',))]
BASELINE = {'name': 'baseline', 'kind': 'baseline', 'what': 'the package parameters', 'params': {}}


def load_variants(path, only):
    with open(path) as f:
        variants = yaml.safe_load(f)['variants']
    names = [v['name'] for v in variants]
    if len(set(names)) != len(names) or 'baseline' in names:
        raise SystemExit('%s: variant names must be unique and not "baseline"' % path)
    if only:
        unknown = set(only) - set(names)
        if unknown:
            raise SystemExit('unknown variants: %s' % ', '.join(sorted(unknown)))
        variants = [v for v in variants if v['name'] in only]
    return variants


def suite_command(a, v, out, params):
    cmd = [sys.executable, os.path.join(os.path.dirname(os.path.abspath(__file__)), 'suite.py'),
           '--tools', a.tools, '--output', out, '--count', str(a.count), '--seed', str(a.seed),
           '--jobs', str(a.jobs)]
    cmd += ['--detector', a.detector] if a.detector else []
    cmd += ['--mesh-dir', a.mesh_dir] if a.mesh_dir else []
    if v['name'] == 'baseline':
        return cmd + ['--keep-bags']
    return cmd + ['--bags', os.path.join(a.output, 'baseline'), '--evaluate-args',
                  '--params ' + params]


def scored(out, settings):
    """The summary of an earlier run of this variant with the same settings, else None."""
    try:
        with open(os.path.join(out, 'summary.json')) as f:
            summary = json.load(f)
        with open(os.path.join(out, 'variant.json')) as f:
            same = json.load(f) == settings
        return summary if same and not summary['failed'] else None
    except (OSError, ValueError, KeyError):
        return None


def run_variant(a, v):
    out = os.path.join(a.output, v['name'])
    os.makedirs(out, exist_ok=True)
    params = os.path.join(out, 'params.yaml')
    with open(params, 'w') as f:
        yaml.safe_dump(v['params'], f, default_flow_style=False)
    settings = {'params': v['params'], 'count': a.count, 'seed': a.seed, 'detector': a.detector,
                'mesh_dir': a.mesh_dir}
    summary = None if a.rerun else scored(out, settings)
    if summary is not None:
        print('ablation: %s already scored (%s)' % (v['name'], out), flush=True)
        return summary
    t0 = time.time()
    print('ablation: %s: %s %s' % (v['name'], v['what'], json.dumps(v['params'])), flush=True)
    with open(os.path.join(out, 'suite.log'), 'w') as log:
        rc = subprocess.run(suite_command(a, v, out, params), stdout=log,
                            stderr=subprocess.STDOUT).returncode
    with open(os.path.join(out, 'summary.json')) as f:
        summary = json.load(f)
    if rc == 0:
        with open(os.path.join(out, 'variant.json'), 'w') as f:
            json.dump(settings, f)
    print('ablation: %s done in %.0f s: %s' % (v['name'], time.time() - t0,
                                               suite_summary.headline(summary)), flush=True)
    return summary


def figures(summary):
    out = {}
    for name, _, stats in FIGURES:
        s = suite_summary.get_nested(summary, name) or {}
        out[name] = {k: s.get(k) for k in stats}
    out['per_scenario_recall'] = {
        e['name']: suite_summary.get_nested(e.get('report') or {}, 'objects.recall_add_or_adds_10')
        for e in summary['scenarios']}
    out['failed'] = summary['failed']
    return out


def cell(value, base):
    if value is None:
        return '—'
    text = suite_summary.fmt(value)
    if base is None or value == base:
        return text
    return '%s (%+.3g)' % (text, value - base)


def changed(rows, name):
    """Scenarios whose ADD(-S) recall differs from the baseline's by 0.005 or more."""
    base, mine = rows['baseline']['per_scenario_recall'], rows[name]['per_scenario_recall']
    return sum(1 for s, r in mine.items()
               if r is not None and base.get(s) is not None and abs(r - base[s]) >= 0.005)


def markdown(variants, rows, a):
    hypotheses = 'the detector (%s)' % a.detector if a.detector else 'simulated hypotheses'
    lines = ['# Ablation on the suite of %d (seed %d), %s' % (a.count, a.seed, hypotheses), '',
             'Each row: the suite with one variant of the parameters; in brackets the difference '
             'to the baseline. "changed": scenarios whose ADD(-S) recall moved by 0.005 or more. '
             'Frame times depend on what else the machine ran beside each variant.', '']
    head = ['variant', 'kind', 'what', 'parameters']
    head += ['%s %s' % (label, s) for _, label, stats in FIGURES for s in stats] + ['changed']
    lines += ['| ' + ' | '.join(head) + ' |', '|' + '---|' * len(head)]
    for v in variants:
        if v['name'] not in rows:
            continue
        r, b = rows[v['name']], rows['baseline']
        cells = [v['name'], v['kind'], v['what'],
                 ', '.join('`%s: %s`' % kv for kv in sorted(flatten(v['params']).items()))]
        for name, _, stats in FIGURES:
            cells += [cell(r[name][s], b[name][s]) for s in stats]
        cells.append(str(changed(rows, v['name'])))
        lines.append('| ' + ' | '.join(cells) + ' |')
    return '\n'.join(lines) + '\n'


def flatten(tree, prefix=''):
    out = {}
    for k, v in tree.items():
        if isinstance(v, dict):
            out.update(flatten(v, prefix + k + '/'))
        else:
            out[prefix + k] = v
    return out


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawTextHelpFormatter)
    ap.add_argument('--tools', required=True)
    ap.add_argument('--output', required=True)
    ap.add_argument('--variants', default=os.path.join(
        os.path.dirname(os.path.dirname(os.path.abspath(__file__))), 'config', 'ablation.yaml'))
    ap.add_argument('--only', default='', help='comma-separated variant names (default: all)')
    ap.add_argument('--count', type=int, default=20)
    ap.add_argument('--seed', type=int, default=1)
    ap.add_argument('--detector', default='')
    ap.add_argument('--mesh-dir', default='')
    ap.add_argument('--jobs', type=int, default=2)
    ap.add_argument('--rerun', action='store_true', help='score variants again')
    a = ap.parse_args()
    a.output = os.path.abspath(a.output)
    a.mesh_dir = os.path.abspath(a.mesh_dir) if a.mesh_dir else ''
    variants = [BASELINE] + load_variants(a.variants, [n for n in a.only.split(',') if n])
    rows = {}
    for i, v in enumerate(variants):
        print('ablation: [%d/%d] %s' % (i + 1, len(variants), v['name']), flush=True)
        rows[v['name']] = figures(run_variant(a, v))
        with open(os.path.join(a.output, 'ablation.json'), 'w') as f:
            json.dump({'variants': [dict(v, figures=rows[v['name']]) for v in variants
                                    if v['name'] in rows]}, f, indent=1)
        with open(os.path.join(a.output, 'ablation.md'), 'w') as f:
            f.write(markdown(variants, rows, a))
    print('ablation: wrote %s' % os.path.join(a.output, 'ablation.md'))
    return 0 if all(r['failed'] == 0 for r in rows.values()) else 1


if __name__ == '__main__':
    sys.exit(main())
