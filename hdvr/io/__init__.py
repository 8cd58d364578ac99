"""File formats: 2D keypoint NPZ, 3D result NPZ, OpenPose / COCO JSON readers, BVH reader and writer."""

#: file name suffixes of the pictures the commands write (PNG or JPEG, by OpenCV or matplotlib)
PICTURE_SUFFIXES = (".png", ".jpg", ".jpeg")
