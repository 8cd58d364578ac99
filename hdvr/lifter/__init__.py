"""Temporal 2D-to-3D lifter trained on top of the unsupervised fit (the paper's Algorithm 4*).

- :mod:`hdvr.lifter.model`   dilated temporal convolution network (the architecture family of VideoPose3D)
- :mod:`hdvr.lifter.losses`  the loss terms of Algorithm 4* (reprojection, fit consistency, temporal smoothness)
- :mod:`hdvr.lifter.data`    training windows from (2D keypoint file, 3D fit result) pairs
- :mod:`hdvr.lifter.train`   training loop, checkpoints, and inference over whole clips
"""
