#!/usr/bin/python3
"""The ablation (scripts/ablation.py): its variants file against the parameter defaults, and its
table on hand-made suite summaries.

  /usr/bin/python3 test/python/test_ablation.py [--xml=RESULT.xml]
"""
import argparse
import os
import sys
import unittest

import yaml

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.join(HERE, '..', '..')
sys.path.insert(0, HERE)
sys.path.insert(0, os.path.join(ROOT, 'scripts'))
import ablation  # noqa: E402
import junit_runner  # noqa: E402


def summary(recalls, switches):
    scenarios = [{'name': 'scenario_%03d' % i, 'report': {'objects': {'recall_add_or_adds_10': r}}}
                 for i, r in enumerate(recalls)]
    return {'failed': 0, 'scenarios': scenarios,
            'objects': {'recall_add_or_adds_10': {'median': sorted(recalls)[len(recalls) // 2],
                                                  'worst': min(recalls), 'mean': 0.8},
                        'identity_switches': {'median': switches, 'worst': switches}}}


class AblationTest(unittest.TestCase):
    def test_every_variant_changes_existing_parameters(self):
        with open(os.path.join(ROOT, 'config', 'tracker.yaml')) as f:
            defaults = ablation.flatten(yaml.safe_load(f))
        variants = ablation.load_variants(os.path.join(ROOT, 'config', 'ablation.yaml'), [])
        self.assertGreater(len(variants), 10)
        for v in variants:
            self.assertIn(v['kind'], ('rule', 'candidate'), v['name'])
            params = ablation.flatten(v['params'])
            self.assertTrue(params, v['name'])
            for key, value in params.items():
                self.assertIn(key, defaults, '%s: %s is no parameter' % (v['name'], key))
                self.assertNotEqual(value, defaults[key], '%s: %s is its default' % (v['name'], key))

    def test_only_picks_named_variants_and_rejects_unknown_names(self):
        path = os.path.join(ROOT, 'config', 'ablation.yaml')
        self.assertEqual([v['name'] for v in ablation.load_variants(path, ['no_pulls'])],
                         ['no_pulls'])
        with self.assertRaises(SystemExit):
            ablation.load_variants(path, ['no_such_rule'])

    def test_the_table_gives_each_variant_against_the_baseline(self):
        a = argparse.Namespace(count=3, seed=1, detector='')
        variants = [ablation.BASELINE,
                    {'name': 'no_x', 'kind': 'rule', 'what': 'x off', 'params': {'x': {'y': 0}}}]
        rows = {'baseline': ablation.figures(summary([0.9, 0.8, 0.7], 2)),
                'no_x': ablation.figures(summary([0.9, 0.6, 0.7], 3))}
        self.assertEqual(ablation.changed(rows, 'no_x'), 1)
        table = ablation.markdown(variants, rows, a)
        no_x = [line for line in table.splitlines() if line.startswith('| no_x')][0]
        self.assertIn('`x/y: 0`', no_x)
        self.assertIn('0.600 (-0.1)', no_x)  # the worst recall and its difference
        self.assertIn('3 (+1)', no_x)  # switches
        self.assertTrue(no_x.endswith('| 1 |'))


if __name__ == '__main__':
    junit_runner.main('ablation', AblationTest)
