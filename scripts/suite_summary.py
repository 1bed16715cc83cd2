"""Summaries of the scenario suite (scripts/suite.py): statistics over the scenarios' report.json
files, by kind of scenario, as JSON, Markdown and a plot of the per-scenario recall."""
import json
import os
import re
import statistics

# Keys where a smaller value is the worse one (recall-like); for every other numeric key (errors,
# switches, false tracks, times, misses) the larger value is the worse one.
LOWER_IS_WORSE = re.compile(r'(recall|precision|reduction|found|evaluated|frames|true_positives|'
                            r'declared|valid_points)')
HEADLINE = [('objects.recall_add_or_adds_10', 'ADD(-S) recall'),
            ('objects.recall_adds_10', 'ADD-S recall'),
            ('objects.add_or_adds_mean_mm', 'ADD(-S) mean (mm)'),
            ('objects.rotation_error_mean_deg', 'rotation error (deg)'),
            ('objects.identity_switches', 'identity switches'),
            ('objects.false_tracks', 'false tracks'),
            ('relations.precision', 'relation precision'),
            ('relations.recall', 'relation recall'),
            ('localization.translation_error_mean_mm', 'localization (mm)'),
            ('timing.frame_ms_median', 'frame median (ms)')]


def numeric_leaves(tree, prefix=''):
    """Dotted name -> value for every number in a report, per_object subtrees left out."""
    out = {}
    for k, v in tree.items():
        name = prefix + k
        if k == 'per_object':
            continue
        if isinstance(v, dict):
            out.update(numeric_leaves(v, name + '.'))
        elif isinstance(v, (int, float)) and not isinstance(v, bool):
            out[name] = v
    return out


def stats(name, values):
    worst = min(values) if LOWER_IS_WORSE.search(name.split('.')[-1]) else max(values)
    return {'median': statistics.median(values), 'worst': worst, 'mean': statistics.fmean(values)}


def set_nested(tree, dotted, value):
    *path, last = dotted.split('.')
    for p in path:
        tree = tree.setdefault(p, {})
    tree[last] = value


def get_nested(tree, dotted):
    for p in dotted.split('.'):
        if not isinstance(tree, dict) or p not in tree:
            return None
        tree = tree[p]
    return tree


def aggregate(reports):
    values = {}
    for r in reports:
        for name, v in numeric_leaves(r).items():
            values.setdefault(name, []).append(v)
    out = {}
    for name in sorted(values):
        set_nested(out, name, stats(name, values[name]))
    return out


# Per-object hypothesis errors (report.json hypotheses.per_object) that hypotheses_by_class sums up.
HYPOTHESIS_ERRORS = ('translation_error_median_mm', 'rotation_error_median_deg',
                     'rotation_error_up_to_box_turns_median_deg')


def hypotheses_by_class(entries):
    """Per class over all scenarios: in-view object frames, those with a hypothesis assigned
    (one to one, within the object's gate), and their share: the detection rate; and, over the
    class's objects with a hypothesis, the median of their hypotheses' median errors (HYPOTHESIS_ERRORS).
    Classes come from the scenario (`classes`: id -> class), else from the report's scored objects."""
    out, errors = {}, {}
    for e in entries:
        r = e['report']
        classes = {i: o['class'] for i, o in r['objects'].get('per_object', {}).items()}
        classes.update(e.get('classes', {}))
        for i, h in r.get('hypotheses', {}).get('per_object', {}).items():
            name = classes.get(i, '?')
            c = out.setdefault(name, {'evaluated': 0, 'found': 0})
            c['evaluated'] += h['evaluated']
            c['found'] += h['found']
            for key in HYPOTHESIS_ERRORS:
                if h['found'] and h.get(key) is not None:
                    errors.setdefault(name, {}).setdefault(key, []).append(h[key])
    for name, c in out.items():
        c['rate'] = c['found'] / c['evaluated'] if c['evaluated'] else None
        for key in HYPOTHESIS_ERRORS:
            vals = errors.get(name, {}).get(key)
            c[key] = statistics.median(vals) if vals else None
    return dict(sorted(out.items()))


ALWAYS_COUNTED = ('displaced', 'turned', 'missed')
FAILURES = ALWAYS_COUNTED + ('crossed',)  # crossed: counted by newer reports only


def objects_by_class(reports):
    """Per class over the reports' scored objects: the object-frame recall (each object's
    ADD(-S) recall weighted by its scored frames) and the shares of those frames displaced,
    turned, missed and crossed (None where the reports do not count crossed frames)."""
    totals = {}
    for report in reports:
        for o in (get_nested(report, 'objects.per_object') or {}).values():
            n = o.get('evaluated', 0)
            if not n or o.get('recall_add_or_adds_10') is None:
                continue
            t = totals.setdefault(o['class'], dict({'evaluated': 0, 'correct': 0.0},
                                                   **{k: 0 for k in FAILURES}))
            t['evaluated'] += n
            t['correct'] += o['recall_add_or_adds_10'] * n
            for k in FAILURES:
                t[k] += o.get(k, 0)
            t['has_crossed'] = t.get('has_crossed', False) or 'crossed' in o  # newer reports
    out = {}
    for cls, t in sorted(totals.items()):
        n = t['evaluated']
        out[cls] = {'object_frames': n, 'recall': t['correct'] / n,
                    **{k: t[k] / n for k in ALWAYS_COUNTED},
                    'crossed': t['crossed'] / n if t['has_crossed'] else None}
    return out


def worst_objects(entries, count=10):
    """The `count` scored objects of lowest ADD(-S) recall over all scenarios, with their scored
    frames, how many of those were displaced, turned, missed and crossed, and their switches."""
    rows = []
    for e in entries:
        for oid, o in (get_nested(e.get('report') or {}, 'objects.per_object') or {}).items():
            if o.get('evaluated') and o.get('recall_add_or_adds_10') is not None:
                rows.append(dict({'scenario': e['name'], 'object': oid, 'class': o['class'],
                                  'recall': float(o['recall_add_or_adds_10']),
                                  'frames': o['evaluated'],
                                  'switches': o.get('identity_switches', 0)},
                                 **{k: o.get(k) for k in FAILURES}))
    rows.sort(key=lambda r: (r['recall'], r['scenario'], r['object']))
    return rows[:count]


def summarise(entries, settings):
    ok = [e for e in entries if 'report' in e]
    summary = {'settings': settings, 'scenario_count': len(entries), 'failed': len(entries) - len(ok)}
    summary.update(aggregate([e['report'] for e in ok]))
    kinds = sorted({k for e in ok for k in e['kinds']})
    summary['hypotheses_by_class'] = hypotheses_by_class(ok)
    summary['objects_by_class'] = objects_by_class(e['report'] for e in ok)
    summary['worst_objects'] = worst_objects(ok)
    summary['by_kind'] = {}
    for kind in kinds:
        reports = [e['report'] for e in ok if kind in e['kinds']]
        figures = {'count': len(reports)}
        for name, _ in HEADLINE:
            vals = [v for v in (get_nested(r, name) for r in reports) if v is not None]
            if vals:
                figures[name] = stats(name, vals)
        summary['by_kind'][kind] = figures
    summary['scenarios'] = [{'name': e['name'], 'kinds': e['kinds'], 'status': e['status'],
                             'classes': e.get('classes'),
                             'seconds': e.get('seconds'), 'scenario': e['index'],
                             'report': e.get('report')} for e in entries]
    return summary


def headline(summary):
    parts = []
    for name, label in HEADLINE[:6]:
        s = get_nested(summary, name)
        if s:
            parts.append('%s median %.3g, worst %.3g' % (label, s['median'], s['worst']))
    if summary['failed']:
        parts.append('%d scenarios FAILED' % summary['failed'])
    return '; '.join(parts)


def fmt(v):
    return '—' if v is None else ('%.3f' % v if isinstance(v, float) else str(v))


def failure_tables(summary):
    """Markdown lines: what fails per class, and the worst objects."""
    lines = ['', '## Objects per class (share of their scored frames)', '',
             '| class | object-frames | ADD(-S) recall | displaced | of them crossed | turned | '
             'missed |', '|---|---|---|---|---|---|---|']
    for c, o in summary['objects_by_class'].items():
        lines.append('| %s | %d | %s | %s | %s | %s | %s |' % (
            c, o['object_frames'], fmt(o['recall']), fmt(o['displaced']), fmt(o['crossed']),
            fmt(o['turned']), fmt(o['missed'])))
    lines += ['', '## Worst objects (scored frames displaced, turned, missed, crossed)', '',
              '| scenario | object | ADD(-S) recall | frames | displaced | turned | missed | '
              'crossed | switches |', '|---|---|---|---|---|---|---|---|---|']
    for w in summary['worst_objects']:
        lines.append('| %s | %s | %s | %d | %s | %s | %s | %s | %d |' % (
            w['scenario'], w['object'], fmt(w['recall']), w['frames'],
            *(fmt(w[k]) for k in FAILURES), w['switches']))
    return lines


def markdown(summary):
    s = summary['settings']
    lines = ['# Scenario suite', '',
             '%d scenarios, seed %d, hypotheses: %s, meshes: %s. Failed: %d.' % (
                 summary['scenario_count'], s['seed'], s['detector'] or 'simulated',
                 s['mesh_dir'] or "the package's", summary['failed']), '',
             '| figure | median | worst | mean |', '|---|---|---|---|']
    for name, label in HEADLINE:
        st = get_nested(summary, name)
        if st:
            lines.append('| %s (`%s`) | %s | %s | %s |' % (label, name, fmt(st['median']),
                                                           fmt(st['worst']), fmt(st['mean'])))
    lines += ['', '## Hypotheses per class (detection rate: in-view frames with a hypothesis; errors: '
              'the median over the objects of their hypotheses\' medians)', '',
              '| class | frames | with a hypothesis | rate | translation error mm | rotation error deg | '
              'up to box half turns deg |', '|---|---|---|---|---|---|---|']
    for c, h in summary['hypotheses_by_class'].items():
        lines.append('| %s | %d | %d | %s | %s | %s | %s |' % (
            c, h['evaluated'], h['found'], fmt(h['rate']),
            *(fmt(h.get(k)) for k in HYPOTHESIS_ERRORS)))
    lines += failure_tables(summary)
    lines += ['', '## By kind of scenario', '',
              '| kind | scenarios | ADD(-S) recall median | worst | switches worst | '
              'false tracks median |', '|---|---|---|---|---|---|']
    for kind, f in summary['by_kind'].items():
        r = f.get('objects.recall_add_or_adds_10', {})
        sw = f.get('objects.identity_switches', {})
        ft = f.get('objects.false_tracks', {})
        lines.append('| %s | %d | %s | %s | %s | %s |' % (kind, f['count'], fmt(r.get('median')),
                     fmt(r.get('worst')), fmt(sw.get('worst')), fmt(ft.get('median'))))
    lines += ['', '## Scenarios', '',
              '| scenario | kinds | ADD(-S) recall | ADD-S recall | switches | false tracks | '
              'relations P / R | frame ms |', '|---|---|---|---|---|---|---|---|']
    for e in summary['scenarios']:
        r = e['report']
        if r is None:
            lines.append('| %s | %s | %s |||||' % (e['name'], ', '.join(e['kinds']), e['status']))
            continue
        o, rel = r['objects'], r.get('relations', {})
        lines.append('| %s | %s | %s | %s | %d | %d | %s / %s | %s |' % (
            e['name'], ', '.join(e['kinds']), fmt(o['recall_add_or_adds_10']),
            fmt(o['recall_adds_10']), o['identity_switches'], o['false_tracks'],
            fmt(rel.get('precision')), fmt(rel.get('recall')), fmt(r['timing']['frame_ms_median'])))
    return '\n'.join(lines) + '\n'


def plot(summary, path):
    import matplotlib
    matplotlib.use('Agg')
    import matplotlib.pyplot as plt
    done = [e for e in summary['scenarios'] if e['report']]
    names = [e['name'].replace('scenario_', '') for e in done]
    honest = [e['report']['objects']['recall_add_or_adds_10'] for e in done]
    adds = [e['report']['objects']['recall_adds_10'] for e in done]
    fig, ax = plt.subplots(figsize=(max(6, 0.45 * len(done) + 2), 4))
    x = range(len(done))
    ax.bar([i - 0.2 for i in x], honest, 0.4, label='ADD(-S) < 0.1 d')
    ax.bar([i + 0.2 for i in x], adds, 0.4, label='ADD-S < 0.1 d', alpha=0.6)
    ax.set_xticks(list(x))
    ax.set_xticklabels(names, rotation=90)
    ax.set_ylim(0, 1.02)
    ax.set_ylabel('recall')
    ax.set_xlabel('scenario')
    ax.set_title('Per-scenario recall (%s)' % (summary['settings']['detector'] or 'simulated hypotheses'))
    ax.legend(loc='lower left')
    fig.tight_layout()
    fig.savefig(path, dpi=100)
    plt.close(fig)


def write(summary, directory):
    with open(os.path.join(directory, 'summary.json'), 'w') as f:
        json.dump(summary, f, indent=1, sort_keys=False)
    with open(os.path.join(directory, 'summary.md'), 'w') as f:
        f.write(markdown(summary))
    plot(summary, os.path.join(directory, 'recall.png'))
