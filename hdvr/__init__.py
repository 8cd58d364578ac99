"""HDVR: hierarchical dance video recognition.

Pipeline (each stage a module with a documented data contract, data flowing one way):

    video -> tracks -> 2D poses -> 3D fit -> lifter -> movements -> genre

Foundation modules:

- :mod:`hdvr.dh`        the paper's Denavit-Hartenberg table (corrected) and a numpy reference FK
- :mod:`hdvr.skeleton`  the MuJoCo digital dancer: bone lengths, batched FK, site Jacobians, limits
- :mod:`hdvr.layouts`   keypoint layouts (BODY_25, COCO-17, H36M-17, CMU BVH) and converters
- :mod:`hdvr.camera`    pinhole camera (x right, y down, z forward, metres; pixels on the image)
- :mod:`hdvr.io`        2D keypoint NPZ, 3D result NPZ, OpenPose/COCO JSON, BVH
"""

__version__ = "0.1.0"
