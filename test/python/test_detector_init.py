#!/usr/bin/python3
"""Warm start of the detector trainer (scripts/detector_init.py) against the shipped model.

  /usr/bin/python3 test/python/test_detector_init.py [--xml=RESULT.xml]

With --xml a JUnit result for catkin's run_tests (make test) is written.
"""
import os
import sys
import unittest

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
sys.path.insert(0, os.path.join(ROOT, "scripts"))
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
MODEL = os.path.join(ROOT, "models", "sgt_keypoints.onnx")

import numpy as np  # noqa: E402
import torch  # noqa: E402

from detector_init import calibrate, load_onnx, module_name  # noqa: E402
from detector_model import KeypointNet  # noqa: E402
import junit_runner  # noqa: E402


def warm_net(images):
    net = KeypointNet(5, 9, 320)
    calibrate(net, load_onnx(net, MODEL), [(images, None)], lambda x: x)
    return net


class WarmStart(unittest.TestCase):
    def test_module_names_follow_the_torch_scopes(self):
        self.assertEqual(module_name("onnx_node!/stem/stem.0/stem.0.0/Conv"), "stem.0.0")
        self.assertEqual(module_name("onnx_node!/s8/s8.1/a/a.0/Conv"), "s8.1.a.0")
        self.assertEqual(module_name("onnx_node!/heads.2/pos_box/Conv"), "heads.2.pos_box")

    def test_the_warm_net_computes_the_exported_model(self):
        import cv2
        torch.manual_seed(1)
        calibration = torch.rand(4, 3, 320, 320)
        net = warm_net(calibration).eval()
        net.decode = True
        image = torch.rand(1, 3, 320, 320)
        reader = cv2.dnn.readNetFromONNX(MODEL)
        reader.setInput(image.numpy())
        expected = reader.forward()
        with torch.no_grad():
            got = net(image).numpy()
        self.assertEqual(got.shape, expected.shape)
        # boxes and keypoints in input pixels (up to 320), scores in 0..1
        self.assertLess(float(np.abs(got - expected).max()), 0.05)
        fresh = KeypointNet(5, 9, 320).eval()
        fresh.decode = True
        with torch.no_grad():
            self.assertGreater(float(np.abs(fresh(image).numpy() - expected).max()), 1.0)  # the check can fail

    def test_train_mode_on_the_calibration_batch_matches_eval(self):
        torch.manual_seed(2)
        batch = torch.rand(4, 3, 320, 320)
        net = warm_net(batch)
        with torch.no_grad():
            train = net.train()(batch)
            evaluation = net.eval()(batch)
        for (p, s, l), (pe, se, le) in zip(train, evaluation):
            for a, b in ((p, pe), (s, se), (l, le)):
                self.assertLess(float((a - b).abs().max()), 1e-2)

    def test_the_weights_export_for_another_input_size(self):
        import tempfile
        import cv2
        from detector_export import export
        net = KeypointNet(5, 9, (384, 288))
        load_onnx(net, MODEL)  # eval mode needs no calibration
        with tempfile.TemporaryDirectory() as tmp:
            path = os.path.join(tmp, "wide.onnx")
            export(net, path, (384, 288))  # raises when OpenCV's output differs from torch's
            reader = cv2.dnn.readNetFromONNX(path)
            reader.setInput(np.random.rand(1, 3, 288, 384).astype(np.float32))
            out = reader.forward()
        anchors = sum((384 // s) * (288 // s) for s in (8, 16, 32))
        self.assertEqual(out.shape, (1, 4 + 5 + 3 * 9, anchors))

    def test_a_model_of_another_shape_is_refused_with_the_shapes(self):
        net = KeypointNet(5, 9, 320, head=32)
        with self.assertRaises(RuntimeError) as err:
            load_onnx(net, MODEL)
        self.assertIn("heads.0.box.0 has shape (48, 48, 3, 3), the network (32, 48, 3, 3)", str(err.exception))


if __name__ == "__main__":
    junit_runner.main("detector_init", WarmStart)
