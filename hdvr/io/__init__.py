"""File formats: 2D keypoint NPZ, 3D result NPZ, OpenPose / COCO JSON readers, BVH reader and writer."""
