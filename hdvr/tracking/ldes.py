"""An LDES-style single-target tracker: translation by a kernelised correlation filter on HOG + colour
features, scale and in-plane rotation by phase correlation in log-polar coordinates.

Written here because OpenCV's headless build ships only ``TrackerMIL`` (no KCF/CSRT, no LDES) and no registry
package provides LDES. The method follows the published idea (Li et al., "Robust Estimation of Similarity
Transformation for Visual Object Tracking", AAAI 2019): a correlation filter finds the shift of the target; a
log-polar resampling of the patch turns a change of scale into a shift along the log-radius axis and a rotation
into a shift along the angle axis, which phase correlation measures.

Conventions: images are BGR uint8 (H, W, 3); boxes are (x, y, w, h) in pixels with (x, y) the top-left corner;
angles are degrees, counter-clockwise in the image as displayed (y down), i.e. ``cv2.getRotationMatrix2D``'s sense.
"""

from __future__ import annotations

from dataclasses import dataclass

import cv2
import numpy as np
import scipy.fft as sfft

from hdvr.errors import HDVRError


@dataclass(frozen=True)
class LDESConfig:
    """Tracker parameters (defaults tuned on the procedural test clips)."""

    padding: float = 1.0  # search window = target size * (1 + padding), per side length
    template_max_side: int = 128  # pixels of the resampled search window's longer side
    cell_size: int = 4  # HOG cell, pixels of the template
    orientation_bins: int = 9  # unsigned gradient orientations
    output_sigma: float = 0.1  # Gaussian label width, fraction of the target size (in cells)
    kernel_sigma: float = 0.2  # Gaussian kernel width of the KCF
    regularisation: float = 1e-4
    learning_rate: float = 0.02  # per frame, of the translation filter
    colour_weight: float = 0.3  # weight of the colour-histogram response merged with the filter's (Staple-style)
    colour_learning_rate: float = 0.04
    colour_bins: int = 16  # per BGR channel
    logpolar_size: int = 64  # bins in angle and in log radius
    logpolar_learning_rate: float = 0.05
    estimate_scale: bool = True
    estimate_rotation: bool = True
    max_scale_step: float = 0.08  # largest |log scale| change accepted in one frame
    max_rotation_step: float = 10.0  # largest rotation change accepted in one frame, degrees
    logpolar_radius: float = 1.6  # radius of the log-polar support, fraction of half the shorter box side
    min_phase_response: float = 0.05  # phase-correlation peak below this: scale/rotation unchanged


@dataclass(frozen=True)
class TrackState:
    """Result of one tracker update."""

    center: tuple[float, float]  # (x, y) pixels
    size: tuple[float, float]  # (w, h) pixels of the (unrotated) target rectangle
    angle: float  # degrees since initialisation
    scale: float  # size relative to the initial box
    confidence: float  # peak-to-sidelobe ratio of the correlation response (higher = surer; < ~5 is weak)

    @property
    def box(self) -> tuple[float, float, float, float]:
        """Axis-aligned (x, y, w, h) of the unrotated target rectangle around ``center``."""
        return (self.center[0] - self.size[0] / 2, self.center[1] - self.size[1] / 2, self.size[0], self.size[1])


def _hann(h: int, w: int) -> np.ndarray:
    return np.outer(np.hanning(h + 2)[1:-1], np.hanning(w + 2)[1:-1]).astype(np.float32)


def _gaussian_labels(h: int, w: int, sigma_y: float, sigma_x: float) -> np.ndarray:
    """Gaussian peak at (0, 0) with cyclic wrap (KCF convention)."""
    ys = np.fft.ifftshift(np.arange(h) - h // 2)
    xs = np.fft.ifftshift(np.arange(w) - w // 2)
    return np.exp(-0.5 * ((ys[:, None] / sigma_y) ** 2 + (xs[None, :] / sigma_x) ** 2)).astype(np.float32)


def hog_colour_features(patch_bgr: np.ndarray, cell: int, bins: int) -> np.ndarray:
    """Per-cell features of a patch: ``bins`` gradient-orientation channels (normalised per cell), the cell's
    luma and its two chroma channels (YCrCb); returns (H/cell, W/cell, bins + 3) float32."""
    h, w = patch_bgr.shape[:2]
    ch, cw = h // cell, w // cell
    patch_bgr = patch_bgr[: ch * cell, : cw * cell]
    ycc = cv2.cvtColor(patch_bgr, cv2.COLOR_BGR2YCrCb)
    grey = ycc[..., 0].astype(np.float32) / 255.0
    gx = cv2.Sobel(grey, cv2.CV_32F, 1, 0, ksize=1)
    gy = cv2.Sobel(grey, cv2.CV_32F, 0, 1, ksize=1)
    mag, ang = cv2.cartToPolar(gx, gy)
    ang = np.mod(ang, np.pi) * (bins / np.pi)  # unsigned orientation in bin units
    lo = np.floor(ang).astype(np.int32)
    frac = ang - lo
    lo %= bins
    hi = (lo + 1) % bins
    # soft-binned orientation histograms of all cells at once: one bincount over (cell, bin) indices
    rows = np.arange(ch * cell) // cell
    cols = np.arange(cw * cell) // cell
    cell_index = (rows[:, None] * cw + cols[None, :]) * bins
    n = ch * cw * bins
    hist = np.bincount((cell_index + lo).ravel(), (mag * (1 - frac)).ravel(), n) + \
        np.bincount((cell_index + hi).ravel(), (mag * frac).ravel(), n)
    hist = hist.reshape(ch, cw, bins).astype(np.float32)
    hist /= np.sqrt((hist ** 2).sum(axis=2, keepdims=True)) + 0.05
    colour = cv2.resize(ycc, (cw, ch), interpolation=cv2.INTER_AREA).astype(np.float32) / 255.0 - 0.5
    return np.concatenate([hist, colour], axis=2)


class LDESTracker:
    """Track one target from an initial box. Call :meth:`update` with each following frame."""

    def __init__(self, frame: np.ndarray, box, config: LDESConfig | None = None):
        self.config = config or LDESConfig()
        self.init(frame, box)

    # ------------------------------------------------------------------ set-up
    def init(self, frame: np.ndarray, box) -> None:
        """(Re)start on ``box`` = (x, y, w, h) pixels in ``frame``; scale 1, angle 0."""
        x, y, w, h = (float(v) for v in box)
        fh, fw = frame.shape[:2]
        if not (w >= 4 and h >= 4):
            raise HDVRError(f"box {box} is too small to track (width and height must be >= 4 px)")
        if x + w <= 0 or y + h <= 0 or x >= fw or y >= fh:
            raise HDVRError(f"box {tuple(box)} lies outside the {fw}x{fh} frame")
        c = self.config
        self.base_size = (w, h)
        self.center = (x + w / 2, y + h / 2)
        self.scale = 1.0
        self.angle = 0.0
        win_w, win_h = w * (1 + c.padding), h * (1 + c.padding)
        px = c.template_max_side / max(win_w, win_h)  # template pixels per image pixel at scale 1
        tw = max(int(round(win_w * px / c.cell_size)), 4) * c.cell_size
        th = max(int(round(win_h * px / c.cell_size)), 4) * c.cell_size
        self._template_size = (tw, th)
        self._image_per_template = (win_w / tw, win_h / th)  # image px per template px at scale 1
        cells = (th // c.cell_size, tw // c.cell_size)
        self._cos_window = _hann(*cells)
        sig_y = np.sqrt(h * w) * px / c.cell_size * c.output_sigma
        self._labels_f = np.fft.fft2(_gaussian_labels(cells[0], cells[1], sig_y, sig_y))
        # log-polar model: sampled from a square patch around the target (rotation needs a square support)
        self._lp_radius = 0.5 * min(w, h) * c.logpolar_radius  # image px at scale 1
        # taper along log radius only: the angle axis is periodic and must not be windowed
        taper = np.hanning(c.logpolar_size + 2)[1:-1]
        self._lp_window = np.tile(taper, (c.logpolar_size, 1)).astype(np.float64)
        self._lp_cartesian_window = _hann(2 * c.logpolar_size, 2 * c.logpolar_size)
        patch = self._sample(frame)
        # target rectangle inside the template (pixels of the template), for the colour model
        self._target_in_template = (w / self._image_per_template[0], h / self._image_per_template[1])
        self._fg_hist, self._bg_hist = self._colour_histograms(patch)
        self._model_x = self._features(patch)
        self._model_alpha_f = self._train(self._model_x)
        self._model_lp = self._logpolar(frame)
        self.confidence = float("inf")

    # ---------------------------------------------------------------- sampling
    def _affine(self, out_size, image_per_out) -> np.ndarray:
        """2x3 matrix mapping output-patch pixels to image pixels (rotation, scale, centre)."""
        a = np.deg2rad(self.angle)
        cos, sin = np.cos(a), np.sin(a)
        sx, sy = image_per_out[0] * self.scale, image_per_out[1] * self.scale
        # a counter-clockwise rotation of the target in the displayed image (y down)
        rot = np.array([[cos, sin], [-sin, cos]])
        lin = rot @ np.diag([sx, sy])
        ox, oy = (out_size[0] - 1) / 2, (out_size[1] - 1) / 2
        t = np.array(self.center) - lin @ np.array([ox, oy])
        return np.hstack([lin, t[:, None]]).astype(np.float64)

    def _sample(self, frame: np.ndarray, center=None) -> np.ndarray:
        old = self.center
        if center is not None:
            self.center = center
        m = self._affine(self._template_size, self._image_per_template)
        self.center = old
        return cv2.warpAffine(frame, m, self._template_size, flags=cv2.INTER_LINEAR | cv2.WARP_INVERSE_MAP,
                              borderMode=cv2.BORDER_REPLICATE)

    def _features(self, patch: np.ndarray) -> np.ndarray:
        f = hog_colour_features(patch, self.config.cell_size, self.config.orientation_bins)
        return f * self._cos_window[..., None]

    # ------------------------------------------------------------ colour model
    def _colour_index(self, patch: np.ndarray) -> np.ndarray:
        q = (patch // (256 // self.config.colour_bins)).astype(np.int32)
        n = self.config.colour_bins
        return (q[..., 0] * n + q[..., 1]) * n + q[..., 2]

    def _colour_histograms(self, patch: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Colour histograms of the target rectangle (foreground) and of the window around it (background)."""
        idx = self._colour_index(patch)
        th, tw = patch.shape[:2]
        w, h = self._target_in_template
        fg = np.zeros((th, tw), bool)
        bg = np.ones((th, tw), bool)
        cx, cy = (tw - 1) / 2, (th - 1) / 2
        fg[int(cy - 0.4 * h): int(cy + 0.4 * h) + 1, int(cx - 0.4 * w): int(cx + 0.4 * w) + 1] = True
        bg[int(cy - 0.6 * h): int(cy + 0.6 * h) + 1, int(cx - 0.6 * w): int(cx + 0.6 * w) + 1] = False
        bins = self.config.colour_bins ** 3
        fg_hist = np.bincount(idx[fg], minlength=bins).astype(np.float32)
        bg_hist = np.bincount(idx[bg], minlength=bins).astype(np.float32)
        return fg_hist / max(fg_hist.sum(), 1), bg_hist / max(bg_hist.sum(), 1)

    def _colour_response(self, patch: np.ndarray, cells: tuple[int, int]) -> np.ndarray:
        """Mean foreground probability of a target-sized box at each cell position, in the cyclic layout of the
        filter response (index 0 = no shift)."""
        likelihood = self._fg_hist / (self._fg_hist + self._bg_hist + 1e-6)
        prob = likelihood[self._colour_index(patch)].astype(np.float32)
        w, h = self._target_in_template
        mean = cv2.boxFilter(prob, -1, (max(int(w * 0.8), 1), max(int(h * 0.8), 1)), normalize=True,
                             borderType=cv2.BORDER_CONSTANT)
        grid = cv2.resize(mean, (cells[1], cells[0]), interpolation=cv2.INTER_AREA)
        return np.fft.ifftshift(grid)

    def _logpolar(self, frame: np.ndarray) -> np.ndarray:
        """Fourier-Mellin descriptor of a square patch around the target, in the tracker's current scale and
        rotation frame: the log-polar resampling (rows: angle over 360 degrees, columns: log radius) of the
        patch's log amplitude spectrum. The amplitude spectrum ignores a residual translation; a rotation of
        the target rotates it, a scaling by s scales it by 1/s."""
        n = self.config.logpolar_size * 2
        m = self._affine((n, n), (2 * self._lp_radius / n, 2 * self._lp_radius / n))
        patch = cv2.warpAffine(frame, m, (n, n), flags=cv2.INTER_LINEAR | cv2.WARP_INVERSE_MAP,
                               borderMode=cv2.BORDER_REPLICATE)
        grey = cv2.cvtColor(patch, cv2.COLOR_BGR2GRAY).astype(np.float32) / 255.0
        grey = (grey - grey.mean()) * self._lp_cartesian_window
        spectrum = np.log1p(np.abs(np.fft.fftshift(np.fft.fft2(grey)))).astype(np.float32)
        k = self.config.logpolar_size
        return cv2.warpPolar(spectrum, (k, k), (n / 2, n / 2), n / 2, cv2.WARP_POLAR_LOG | cv2.INTER_LINEAR)

    # ------------------------------------------------------------- KCF pieces
    def _kernel_f(self, x: np.ndarray, z: np.ndarray) -> np.ndarray:
        xf = sfft.fft2(x, axes=(0, 1))
        zf = sfft.fft2(z, axes=(0, 1))
        cross = np.real(sfft.ifft2((np.conj(xf) * zf).sum(axis=2)))
        d = (x ** 2).sum() + (z ** 2).sum() - 2 * cross
        k = np.exp(-np.maximum(d, 0) / (self.config.kernel_sigma ** 2 * x.size))
        return sfft.fft2(k)

    def _train(self, x: np.ndarray) -> np.ndarray:
        return self._labels_f / (self._kernel_f(x, x) + self.config.regularisation)

    def _respond(self, z: np.ndarray) -> np.ndarray:
        return np.real(sfft.ifft2(self._model_alpha_f * self._kernel_f(self._model_x, z))).astype(np.float32)

    @staticmethod
    def _peak(response: np.ndarray) -> tuple[float, float, float]:
        """Sub-cell peak (dy, dx) as a cyclic shift, and the peak-to-sidelobe ratio."""
        h, w = response.shape
        iy, ix = np.unravel_index(int(np.argmax(response)), response.shape)

        def parabola(m1, c0, p1):
            den = m1 - 2 * c0 + p1
            return 0.0 if abs(den) < 1e-12 else float(np.clip(0.5 * (m1 - p1) / den, -0.5, 0.5))

        dy = iy + parabola(response[(iy - 1) % h, ix], response[iy, ix], response[(iy + 1) % h, ix])
        dx = ix + parabola(response[iy, (ix - 1) % w], response[iy, ix], response[iy, (ix + 1) % w])
        if dy > h / 2:
            dy -= h
        if dx > w / 2:
            dx -= w
        shifted = np.roll(response, (h // 2 - iy, w // 2 - ix), axis=(0, 1))
        mask = np.ones_like(shifted, bool)
        r = max(1, min(h, w) // 8)
        mask[h // 2 - r: h // 2 + r + 1, w // 2 - r: w // 2 + r + 1] = False
        side = shifted[mask]
        psr = (response[iy, ix] - side.mean()) / (side.std() + 1e-6)
        return dy, dx, float(psr)

    # ------------------------------------------------------------------ update
    def predict_translation(self, frame: np.ndarray) -> tuple[tuple[float, float], float]:
        """The new centre found by the correlation filter (pixels) and its peak-to-sidelobe ratio."""
        c = self.config
        patch = self._sample(frame)
        z = self._features(patch)
        response = self._respond(z)
        if c.colour_weight > 0:
            response = (1 - c.colour_weight) * response + c.colour_weight * self._colour_response(patch,
                                                                                                response.shape)
        dy, dx, psr = self._peak(response)
        d_template = np.array([dx, dy]) * c.cell_size
        m = self._affine(self._template_size, self._image_per_template)
        shift = m[:, :2] @ d_template
        return (self.center[0] + float(shift[0]), self.center[1] + float(shift[1])), psr

    def update(self, frame: np.ndarray, learn: bool = True) -> TrackState:
        """Track into ``frame``. With ``learn=False`` the appearance models are not updated (use while the
        target is occluded, so the filter does not learn the occluder)."""
        c = self.config
        self.center, psr = self.predict_translation(frame)
        if c.estimate_scale or c.estimate_rotation:
            lp = self._logpolar(frame)
            (shift_r, shift_a), peak = cv2.phaseCorrelate(self._model_lp.astype(np.float64),
                                                          lp.astype(np.float64), self._lp_window)
            if peak >= c.min_phase_response:
                k = c.logpolar_size
                # warpPolar(LOG): column = k * log(r) / log(maxRadius), maxRadius = patch half-size = k;
                # the spectrum shrinks when the target grows, hence the minus sign
                log_scale = -shift_r * np.log(k) / k
                rotation = shift_a * 360.0 / k
                if c.estimate_scale and abs(log_scale) <= c.max_scale_step:
                    self.scale *= float(np.exp(log_scale))
                if c.estimate_rotation and abs(rotation) <= c.max_rotation_step:
                    self.angle -= float(rotation)
        self.confidence = psr
        if learn:
            patch = self._sample(frame)
            x = self._features(patch)
            if c.colour_weight > 0:
                fg, bg = self._colour_histograms(patch)
                clr = c.colour_learning_rate
                self._fg_hist = (1 - clr) * self._fg_hist + clr * fg
                self._bg_hist = (1 - clr) * self._bg_hist + clr * bg
            lr = c.learning_rate
            self._model_x = (1 - lr) * self._model_x + lr * x
            self._model_alpha_f = (1 - lr) * self._model_alpha_f + lr * self._train(x)
            if c.estimate_scale or c.estimate_rotation:
                llr = c.logpolar_learning_rate
                self._model_lp = (1 - llr) * self._model_lp + llr * self._logpolar(frame)
        return self.state

    @property
    def state(self) -> TrackState:
        w, h = self.base_size
        return TrackState(self.center, (w * self.scale, h * self.scale), self.angle, self.scale,
                          float(self.confidence))
