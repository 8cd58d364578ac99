"""Unsupervised 3D pose fitting of the MuJoCo digital dancer to 2D keypoints (Algorithm 3* and beyond)."""
