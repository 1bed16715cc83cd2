#!/usr/bin/python3
"""The suite's summary (scripts/suite_summary.py) on hand-made report.json figures.

  /usr/bin/python3 test/python/test_suite_summary.py [--xml=RESULT.xml]
"""
import json
import os
import sys
import tempfile
import unittest

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), '..', '..', 'scripts'))
import junit_runner  # noqa: E402
import suite_summary  # noqa: E402


def report(recall, switches, frame_ms, per_object_recall):
    return {'frames': 600,
            'objects': {'recall_add_or_adds_10': recall, 'recall_adds_10': min(1.0, recall + 0.1),
                        'identity_switches': switches, 'false_tracks': 1,
                        'per_object': {'relay_1': {'class': 'relay',
                                                   'recall_adds_10': per_object_recall}},
                        'false_positives_by_class': {'relay': switches}},
            'hypotheses': {'per_object': {'relay_1': {'evaluated': 100, 'found': 50 + switches,
                                                      'rotation_error_median_deg': 10.0 * (1 + switches)}}},
            'relations': {'precision': 1.0, 'recall': recall},
            'timing': {'frame_ms_median': frame_ms}}


class SuiteSummaryTest(unittest.TestCase):
    def setUp(self):
        self.entries = [
            {'name': 'scenario_001', 'kinds': ['carry', 'stack_same'], 'status': 'ok', 'index': {},
             'report': report(0.9, 0, 20.0, 0.1)},
            {'name': 'scenario_002', 'kinds': ['carry'], 'status': 'ok', 'index': {},
             'report': report(0.5, 3, 30.0, 0.2)},
            {'name': 'scenario_003', 'kinds': ['occlusion'], 'status': 'ok', 'index': {},
             'report': report(0.7, 1, 25.0, 0.3)},
            {'name': 'scenario_004', 'kinds': ['occlusion'], 'status': 'simulate failed', 'index': {}},
        ]
        self.summary = suite_summary.summarise(self.entries, {'count': 4, 'seed': 1, 'detector': '',
                                                              'mesh_dir': ''})

    def test_recall_like_keys_are_worst_at_their_minimum(self):
        r = self.summary['objects']['recall_add_or_adds_10']
        self.assertAlmostEqual(r['median'], 0.7)
        self.assertAlmostEqual(r['worst'], 0.5)
        self.assertAlmostEqual(r['mean'], 0.7)
        self.assertAlmostEqual(self.summary['relations']['precision']['worst'], 1.0)

    def test_errors_switches_and_times_are_worst_at_their_maximum(self):
        self.assertEqual(self.summary['objects']['identity_switches']['worst'], 3)
        self.assertEqual(self.summary['objects']['identity_switches']['median'], 1)
        self.assertEqual(self.summary['timing']['frame_ms_median']['worst'], 30.0)
        self.assertEqual(self.summary['objects']['false_positives_by_class']['relay']['worst'], 3)

    def test_per_object_figures_are_not_aggregated(self):
        self.assertNotIn('per_object', self.summary['objects'])

    def test_failed_scenarios_are_counted_and_listed(self):
        self.assertEqual(self.summary['failed'], 1)
        self.assertEqual(len(self.summary['scenarios']), 4)
        self.assertIsNone(self.summary['scenarios'][3]['report'])
        self.assertIn('FAILED', suite_summary.headline(self.summary))

    def test_detection_rate_per_class_sums_the_scenarios_frames(self):
        relay = self.summary['hypotheses_by_class']['relay']
        self.assertEqual(relay['evaluated'], 300)
        self.assertEqual(relay['found'], 50 + 53 + 51)
        self.assertAlmostEqual(relay['rate'], 154 / 300)

    def test_an_object_never_detected_takes_its_class_from_the_scenario(self):
        never = {'name': 'scenario_005', 'kinds': [], 'status': 'ok', 'index': {},
                 'classes': {'relay_9': 'relay'},
                 'report': {'objects': {'per_object': {}},
                            'hypotheses': {'per_object': {'relay_9': {'evaluated': 20, 'found': 0}}}}}
        relay = suite_summary.hypotheses_by_class([never])['relay']
        self.assertEqual((relay['evaluated'], relay['found'], relay['rate']), (20, 0, 0.0))
        self.assertIsNone(relay['rotation_error_median_deg'])  # no hypothesis, no error

    def test_hypothesis_errors_per_class_are_the_median_over_its_objects(self):
        relay = self.summary['hypotheses_by_class']['relay']
        self.assertAlmostEqual(relay['rotation_error_median_deg'], 20.0)  # of 10, 40, 20
        self.assertIsNone(relay['translation_error_median_mm'])  # not in the reports

    def test_by_kind(self):
        carry = self.summary['by_kind']['carry']
        self.assertEqual(carry['count'], 2)
        self.assertAlmostEqual(carry['objects.recall_add_or_adds_10']['worst'], 0.5)
        self.assertEqual(self.summary['by_kind']['occlusion']['count'], 1)

    def test_what_fails_per_class_and_the_worst_objects(self):
        def scored(cls, recall, frames, **failures):
            return dict({'class': cls, 'recall_add_or_adds_10': recall, 'evaluated': frames,
                         'identity_switches': 1}, **failures)
        entries = [
            {'name': 'scenario_001', 'kinds': [], 'status': 'ok',
             'report': {'objects': {'per_object': {
                 'relay_1': scored('relay', 0.5, 100, displaced=30, turned=10, missed=10),
                 'klt_1': scored('klt', 1.0, 300)}}}},
            {'name': 'scenario_002', 'kinds': [], 'status': 'ok',
             'report': {'objects': {'per_object': {
                 'relay_1': scored('relay', 0.9, 300, displaced=10, missed=20, crossed=5),
                 'klt_1': scored('klt', 0.0, 0)}}}},  # never scored: left out
        ]
        relay = suite_summary.objects_by_class(e['report'] for e in entries)['relay']
        self.assertEqual(relay['object_frames'], 400)
        self.assertAlmostEqual(relay['recall'], (0.5 * 100 + 0.9 * 300) / 400)
        self.assertAlmostEqual(relay['displaced'], 40 / 400)
        self.assertAlmostEqual(relay['missed'], 30 / 400)
        self.assertAlmostEqual(relay['crossed'], 5 / 400)
        worst = suite_summary.worst_objects(entries, count=2)
        self.assertEqual([(w['scenario'], w['object']) for w in worst],
                         [('scenario_001', 'relay_1'), ('scenario_002', 'relay_1')])
        self.assertEqual((worst[0]['displaced'], worst[0]['turned'], worst[0]['crossed']),
                         (30, 10, None))
        md = suite_summary.markdown(dict(self.summary, objects_by_class={'relay': relay},
                                         worst_objects=worst))
        self.assertIn('| scenario_001 | relay_1 | 0.500 | 100 | 30 | 10 | 10 | — | 1 |', md)

    def test_files_are_written(self):
        with tempfile.TemporaryDirectory() as d:
            suite_summary.write(self.summary, d)
            with open(os.path.join(d, 'summary.json')) as f:
                back = json.load(f)
            self.assertAlmostEqual(back['objects']['recall_add_or_adds_10']['worst'], 0.5)
            with open(os.path.join(d, 'summary.md')) as f:
                md = f.read()
            self.assertIn('| scenario_002 | carry | 0.500 |', md)
            self.assertGreater(os.path.getsize(os.path.join(d, 'recall.png')), 1000)


if __name__ == '__main__':
    junit_runner.main('suite_summary', SuiteSummaryTest)
