#!/usr/bin/python3
"""Two suite runs compared scenario by scenario (scripts/suite_compare.py) on hand-made reports.

  /usr/bin/python3 test/python/test_suite_compare.py [--xml=RESULT.xml]
"""
import json
import os
import sys
import tempfile
import unittest

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), '..', '..', 'scripts'))
import junit_runner  # noqa: E402
import suite_compare  # noqa: E402


def report(recall, objects):
    """objects: [(class, evaluated, recall, displaced, turned, missed)]"""
    return {'objects': {
        'recall_add_or_adds_10': recall, 'identity_switches': 1, 'false_tracks': 2,
        'per_object': {'%s_%d' % (c, i): {'class': c, 'evaluated': n, 'recall_add_or_adds_10': r,
                                          'displaced': d, 'turned': t, 'missed': m}
                       for i, (c, n, r, d, t, m) in enumerate(objects)}}}


def write_suite(root, name, reports):
    for scenario, r in reports.items():
        d = os.path.join(root, name, 'runs', scenario)
        os.makedirs(d)
        with open(os.path.join(d, 'report.json'), 'w') as f:
            json.dump(r, f)
    return os.path.join(root, name)


class SuiteCompareTest(unittest.TestCase):
    def test_sign_test(self):
        self.assertAlmostEqual(suite_compare.sign_test(5, 0), 2.0 / 32.0)
        self.assertAlmostEqual(suite_compare.sign_test(0, 5), 2.0 / 32.0)
        self.assertEqual(suite_compare.sign_test(3, 3), 1.0)
        self.assertEqual(suite_compare.sign_test(0, 0), 1.0)
        # 9 of 10 one way: (1 + 10) / 1024, both tails.
        self.assertAlmostEqual(suite_compare.sign_test(9, 1), 22.0 / 1024.0)

    def test_scenarios_paired_and_classes_weighted_by_their_frames(self):
        with tempfile.TemporaryDirectory() as root:
            base = write_suite(root, 'base', {
                's1': report(0.5, [('relay', 100, 0.5, 30, 10, 10)]),
                's2': report(0.8, [('relay', 300, 0.9, 10, 10, 10),
                                   ('klt', 100, 1.0, 0, 0, 0)]),
                's3': report(0.6, [('klt', 100, 0.6, 40, 0, 0)]),
                'only_base': report(0.1, [('klt', 100, 0.1, 90, 0, 0)])})
            other = write_suite(root, 'other', {
                's1': report(0.7, [('relay', 100, 0.7, 10, 10, 10)]),
                's2': report(0.802, [('relay', 300, 0.9, 10, 10, 10),
                                     ('klt', 100, 1.0, 0, 0, 0)]),
                's3': report(0.4, [('klt', 100, 0.4, 60, 0, 0)])})
            b, o = suite_compare.load_reports(base), suite_compare.load_reports(other)
            result = suite_compare.paired(b, o, 'objects.recall_add_or_adds_10', 0.005)
            self.assertEqual([r['scenario'] for r in result['rows']], ['s1', 's2', 's3'])
            self.assertEqual((result['up'], result['down'], result['equal']), (1, 1, 1))
            self.assertAlmostEqual(result['mean_change'], (0.2 + 0.002 - 0.2) / 3)
            self.assertAlmostEqual(result['base']['worst'], 0.5)
            self.assertAlmostEqual(result['other']['median'], 0.7)
            names = [r['scenario'] for r in result['rows']]
            classes = suite_compare.by_class(b, names)
            # relay: (100 x 0.5 + 300 x 0.9) / 400; its displaced frames (30 + 10) / 400.
            self.assertAlmostEqual(classes['relay']['recall'], 0.8)
            self.assertAlmostEqual(classes['relay']['displaced'], 0.1)
            self.assertEqual(classes['klt']['object_frames'], 200)  # not only_base's
            self.assertIsNone(classes['relay']['crossed'])  # reports from before the key
            s1 = os.path.join(other, 'runs', 's1', 'report.json')
            with open(s1) as f:
                r1 = json.load(f)
            r1['objects']['per_object']['relay_0']['crossed'] = 4
            with open(s1, 'w') as f:
                json.dump(r1, f)
            crossed = suite_compare.by_class(suite_compare.load_reports(other), names)['relay']
            self.assertAlmostEqual(crossed['crossed'], 4 / 400)
            self.assertAlmostEqual(classes['klt']['recall'], 0.8)
            out = os.path.join(root, 'cmp.md')
            self.assertEqual(suite_compare.main([base, other, '--output', out]), 0)
            with open(out) as f:
                text = f.read()
            self.assertIn('| s1 | 0.500 | 0.700 | +0.200 |', text)
            self.assertIn('1 up, 1 down, 1 within 0.005', text)
            self.assertIn('| relay | 400 | 0.800 -> 0.850 |', text)

    def test_pairs_of_other_seeds_are_pooled_by_their_base_directory(self):
        with tempfile.TemporaryDirectory() as root:
            def one(name, recall, frames):
                return write_suite(root, name, {'s1': report(recall, [('klt', frames, recall,
                                                                       0, 0, 0)])})
            runs = [one('seed1_base', 0.5, 100), one('seed1_other', 0.6, 100),
                    one('seed2_base', 0.9, 300), one('seed2_other', 0.8, 300)]
            base, other, empty = suite_compare.load_pairs(runs)
            self.assertIsNone(empty)
            self.assertEqual(sorted(base), ['seed1_base/s1', 'seed2_base/s1'])
            result = suite_compare.paired(base, other, 'objects.recall_add_or_adds_10', 0.005)
            self.assertEqual((result['up'], result['down']), (1, 1))
            self.assertAlmostEqual(result['mean_change'], 0.0)
            self.assertAlmostEqual(suite_compare.by_class(other, sorted(base))['klt']['recall'],
                                   (100 * 0.6 + 300 * 0.8) / 400)
            out = os.path.join(root, 'cmp.md')
            self.assertEqual(suite_compare.main(runs + ['--output', out]), 0)
            with open(out) as f:
                self.assertIn('| seed2_base/s1 | 0.900 | 0.800 | -0.100 |', f.read())
            with self.assertRaises(SystemExit):  # an odd count is not pairs
                suite_compare.main(runs[:3])

    def test_an_empty_run_is_an_error(self):
        with tempfile.TemporaryDirectory() as root:
            base = write_suite(root, 'base', {'s1': report(0.5, [])})
            self.assertEqual(suite_compare.main([base, os.path.join(root, 'none')]), 1)


if __name__ == '__main__':
    junit_runner.main('suite_compare', SuiteCompareTest)
