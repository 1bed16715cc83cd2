#!/usr/bin/env python3
"""Two suite runs of the same scenarios compared scenario by scenario (`make suite` outputs, or
`scripts/suite.py --output` directories), to judge a change on the suite rather than on its
medians alone: with the built-in detector single scenarios swing by 0.1 between runs that differ
in little, so a median can move by chance.

  scripts/suite_compare.py BASE OTHER [BASE2 OTHER2 ...] [--key objects.recall_add_or_adds_10]
                           [--equal 0.005] [--output FILE.md]

Reads BASE/runs/*/report.json and OTHER/runs/*/report.json and prints (and writes to --output):
- per scenario both runs have: the key in each, its change, switches and false tracks;
- how many scenarios went up, down or stayed within --equal, the two-sided sign test's p value
  (ties left out) and the mean change with its standard error;
- per class: recall over the scored object-frames (each object's recall weighted by its scored
  frames), and the share of scored object-frames displaced (of them crossed: on another object of
  the class), turned and missed.
More pairs (the same two builds on suites of other seeds) are pooled: their scenarios count as
one sample, named BASE's directory name/scenario. One suite of 20 cannot tell a mean change below
about 0.03 with the detector from the change a 1 % shift of a stopping threshold makes.
"""
import argparse
import glob
import json
import math
import os
import statistics
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import suite_summary  # noqa: E402


def load_reports(directory):
    """{scenario name: report.json} of a suite output directory."""
    reports = {}
    for path in sorted(glob.glob(os.path.join(directory, 'runs', '*', 'report.json'))):
        with open(path) as f:
            reports[os.path.basename(os.path.dirname(path))] = json.load(f)
    return reports


def sign_test(up, down):
    """Two-sided p value of up ups against down downs under 'either way alike' (ties left out)."""
    n = up + down
    if n == 0:
        return 1.0
    tail = sum(math.comb(n, i) for i in range(min(up, down) + 1)) / 2.0 ** n
    return min(1.0, 2.0 * tail)


def paired(base, other, key, equal):
    rows = []
    for name in sorted(set(base) & set(other)):
        a = suite_summary.get_nested(base[name], key)
        b = suite_summary.get_nested(other[name], key)
        if a is None or b is None:
            continue
        def both(k):
            return (suite_summary.get_nested(base[name], k),
                    suite_summary.get_nested(other[name], k))
        rows.append({'scenario': name, 'base': a, 'other': b, 'change': b - a,
                     'switches': both('objects.identity_switches'),
                     'false_tracks': both('objects.false_tracks')})
    changes = [r['change'] for r in rows]
    up = sum(1 for c in changes if c > equal)
    down = sum(1 for c in changes if c < -equal)
    result = {'rows': rows, 'up': up, 'down': down, 'equal': len(rows) - up - down,
              'sign_test_p': sign_test(up, down)}
    if changes:
        result['mean_change'] = statistics.mean(changes)
        result['mean_change_se'] = (statistics.stdev(changes) / math.sqrt(len(changes))
                                    if len(changes) > 1 else 0.0)
        for side in ('base', 'other'):
            values = [r[side] for r in rows]
            result[side] = {'median': statistics.median(values), 'worst': min(values),
                            'mean': statistics.mean(values)}
    return result


def by_class(reports, names):
    """Per class: object-frame recall and the shares displaced / turned / missed / crossed."""
    return suite_summary.objects_by_class(reports[name] for name in names)


def load_pairs(runs):
    """Reports of BASE OTHER [BASE2 OTHER2 ...]: (base, other, the directory that has none or
    None); with more than one pair, scenario names prefixed with their BASE's directory name."""
    base, other = {}, {}
    names = [os.path.basename(os.path.normpath(r)) for r in runs[::2]]
    if len(runs) > 2 and len(set(names)) < len(names):
        raise ValueError('base directories need distinct names to pool: %s' % ', '.join(names))
    for i in range(0, len(runs), 2):
        b, o = load_reports(runs[i]), load_reports(runs[i + 1])
        if not b or not o:
            return None, None, runs[i] if not b else runs[i + 1]
        prefix = names[i // 2] + '/' if len(runs) > 2 else ''
        base.update({prefix + name: r for name, r in b.items()})
        other.update({prefix + name: r for name, r in o.items()})
    return base, other, None


def markdown(result, classes_base, classes_other, a):
    title = ' + '.join(a.runs[i + 1] for i in range(0, len(a.runs), 2))
    title += ' against ' + ' + '.join(a.runs[i] for i in range(0, len(a.runs), 2))
    lines = ['# %s (%s)' % (title, a.key), '',
             '| scenario | base | other | change | switches | false tracks |',
             '|---|---|---|---|---|---|']
    for r in result['rows']:
        lines.append('| %s | %.3f | %.3f | %+.3f | %s -> %s | %s -> %s |' % (
            r['scenario'], r['base'], r['other'], r['change'], r['switches'][0], r['switches'][1],
            r['false_tracks'][0], r['false_tracks'][1]))
    lines.append('')
    if result['rows']:
        b, o = result['base'], result['other']
        lines.append('%d scenarios: %d up, %d down, %d within %.3f; sign test p = %.3f; '
                     'mean change %+.4f +- %.4f (standard error)' % (
                         len(result['rows']), result['up'], result['down'], result['equal'],
                         a.equal, result['sign_test_p'], result['mean_change'],
                         result['mean_change_se']))
        lines.append('median / worst / mean: %.3f / %.3f / %.3f -> %.3f / %.3f / %.3f' % (
            b['median'], b['worst'], b['mean'], o['median'], o['worst'], o['mean']))
    lines += ['', '| class | object-frames | recall | displaced | of them crossed | turned | missed |',
              '|---|---|---|---|---|---|---|']
    for cls in sorted(set(classes_base) | set(classes_other)):
        cb, co = classes_base.get(cls), classes_other.get(cls)

        def pair(k):
            def one(c):
                return '%.3f' % c[k] if c and c[k] is not None else '-'
            return '%s -> %s' % (one(cb), one(co))
        frames = (co or cb)['object_frames']
        lines.append('| %s | %d | %s | %s | %s | %s | %s |' % (
            cls, frames, pair('recall'), pair('displaced'), pair('crossed'), pair('turned'),
            pair('missed')))
    return '\n'.join(lines) + '\n'


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split('\n')[0])
    ap.add_argument('runs', nargs='+', metavar='BASE OTHER',
                    help='suite output directories in pairs: a base, then the run compared with it')
    ap.add_argument('--key', default='objects.recall_add_or_adds_10')
    ap.add_argument('--equal', type=float, default=0.005,
                    help='a change within this counts as no change')
    ap.add_argument('--output', help='also write the comparison to this markdown file')
    a = ap.parse_args(argv)
    if len(a.runs) % 2:
        ap.error('give the suite directories in pairs: BASE OTHER [BASE2 OTHER2 ...]')
    try:
        base, other, empty = load_pairs(a.runs)
    except ValueError as e:
        ap.error(str(e))
    if empty is not None:
        print('suite_compare: no runs/*/report.json in %s' % empty, file=sys.stderr)
        return 1
    result = paired(base, other, a.key, a.equal)
    names = [r['scenario'] for r in result['rows']]
    text = markdown(result, by_class(base, names), by_class(other, names), a)
    sys.stdout.write(text)
    if a.output:
        with open(a.output, 'w') as f:
            f.write(text)
    return 0


if __name__ == '__main__':
    sys.exit(main())
