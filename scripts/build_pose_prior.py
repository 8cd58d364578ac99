"""Build ``hdvr/data/pose_prior.npz``: a Gaussian mixture over the dancer's 34 hinge angles (radians), fitted by EM
on HDVR's own synthetic choreographies (:mod:`hdvr.synth`, all genres; no real 3D data). Deterministic by seed.

    python3 scripts/build_pose_prior.py [--clips-per-genre 24] [--seconds 20] [--components 32] [--seed 0]
                                        [--covariance-floor-deg 6] [--genres all] [--held-out-clips-per-genre 6]
                                        [--out hdvr/data/pose_prior.npz]

``--genres ballet`` (or any comma-separated genres) builds a prior for one style, for ``hdvr fit3d --pose-prior``
and ``hdvr run --pose-prior``. The build also reports the mixture's mean log-likelihood on clips of another seed,
the measure ``--components`` is chosen by.

Hinges whose synthetic range is narrower than the fitting range (the anatomical widening of
:mod:`hdvr.fitting.limits`: elbow and trunk flexion; the synthetic dancer keeps the paper's bounds there) are
marginalised out: the prior says nothing about them rather than pull them back into the paper's range.

Every component's covariance gets ``(covariance floor)^2`` added to its diagonal, inside EM. The generator barely
moves some hinges that real dancers do move (hip rotation and adduction: 4-8 deg standard deviation over all
poses, ankle inversion 1.5 deg; salsa dancers turn the hips out by about 10 deg and invert the ankles by 10-20):
without a floor the prior pins them at the generator's neutral angle within 2 deg and the fit bends the legs in
depth to make up for it (docs/fitting.md, "Learned pose prior").
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

REPO = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(REPO))

import numpy as np  # noqa: E402

from hdvr import dh  # noqa: E402
from hdvr.fitting.limits import ANATOMICAL_WIDENING  # noqa: E402
from hdvr.synth.genres import GENRES, parse_genres  # noqa: E402
from hdvr.synth.groundtruth import clip_spec, generate_motion  # noqa: E402

OUT = REPO / "hdvr" / "data" / "pose_prior.npz"


def synthetic_hinges(clips_per_genre: int, seconds: float, seed: int, every: int,
                     genres: tuple[str, ...] = GENRES) -> np.ndarray:
    """(N, 34) hinge angles (radians) of every dancer of ``clips_per_genre`` clips per genre, every ``every``-th
    frame."""
    rows = []
    for index in range(clips_per_genre * len(genres)):
        spec = clip_spec(index, seed, genres, (1, 2), seconds)
        dancers, _ = generate_motion(spec)
        rows += [d.qpos[::every, 7:] for d in dancers]
    return np.concatenate(rows)


def fit_gmm(x: np.ndarray, k: int, seed: int, iters: int = 100, reg: float = 1e-3
            ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Full-covariance Gaussian mixture by EM (k-means++ start). Returns weights (k,), means (k, D),
    covariances (k, D, D); ``reg`` (rad^2) is added to every covariance's diagonal."""
    rng = np.random.default_rng(seed)
    n, d = x.shape
    centres = [x[rng.integers(n)]]
    for _ in range(1, k):
        d2 = np.min([np.sum((x - c) ** 2, axis=1) for c in centres], axis=0)
        centres.append(x[rng.choice(n, p=d2 / d2.sum())])
    means = np.array(centres)
    resp = np.eye(k)[np.argmin(((x[:, None] - means[None]) ** 2).sum(-1), axis=1)]
    previous = -np.inf
    for _ in range(iters):
        nk = resp.sum(axis=0) + 1e-10
        weights = nk / n
        means = resp.T @ x / nk[:, None]
        covs = np.empty((k, d, d))
        for j in range(k):
            c = x - means[j]
            covs[j] = (resp[:, j, None] * c).T @ c / nk[j] + reg * np.eye(d)
        loglik = component_loglik(x, weights, means, covs)
        total = np.logaddexp.reduce(loglik, axis=1)
        resp = np.exp(loglik - total[:, None])
        if total.mean() - previous < 1e-5:
            break
        previous = total.mean()
    return weights, means, covs


def component_loglik(x: np.ndarray, weights, means, covs) -> np.ndarray:
    """(N, k) log(pi_k N(x; mu_k, Sigma_k))."""
    out = np.empty((len(x), len(weights)))
    for j in range(len(weights)):
        chol = np.linalg.cholesky(covs[j])
        z = np.linalg.solve(chol, (x - means[j]).T)
        logdet = 2 * np.log(np.diag(chol)).sum()
        out[:, j] = np.log(weights[j]) - 0.5 * (z * z).sum(0) - 0.5 * (logdet + x.shape[1] * np.log(2 * np.pi))
    return out


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--clips-per-genre", type=int, default=24)
    ap.add_argument("--seconds", type=float, default=20.0)
    ap.add_argument("--every", type=int, default=3, help="keep every n-th frame")
    ap.add_argument("--components", type=int, default=32,
                    help="mixture components (32: the most held-out log-likelihood of 12, 20, 32, 48; session 44)")
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--covariance-floor-deg", type=float, default=6.0,
                    help="standard deviation (deg) added in quadrature to every hinge of every component")
    ap.add_argument("--genres", default="all",
                    help="comma-separated genres to learn from (default all nine): a prior for one style, used "
                         "with `hdvr fit3d --pose-prior`")
    ap.add_argument("--held-out-clips-per-genre", type=int, default=6,
                    help="also report the mean log-likelihood of this many clips per genre of another seed "
                         "(seed + 1): how well the mixture generalises, to choose --components (0: skip)")
    ap.add_argument("--out", default=str(OUT))
    args = ap.parse_args()
    genres = parse_genres(args.genres)
    clock = time.process_time()
    hinges = synthetic_hinges(args.clips_per_genre, args.seconds, args.seed, args.every, genres)
    free = np.array([dh.JOINT_NAMES.index(name) for name in ANATOMICAL_WIDENING])
    kept = np.setdiff1d(np.arange(hinges.shape[1]), free)
    weights, means, covs = fit_gmm(hinges[:, kept], args.components, args.seed,
                                   reg=np.deg2rad(args.covariance_floor_deg) ** 2)
    k, d = len(weights), hinges.shape[1]
    mean_full = np.zeros((k, d))
    sqrt_precision = np.zeros((k, d, d))  # rows: L_k^T restricted to the kept hinges, zero columns elsewhere
    log_norm = np.empty(k)  # -2 log(pi_k) + log det Sigma_k: the component's constant in -2 log p
    for j in range(k):
        mean_full[j, kept] = means[j]
        chol = np.linalg.cholesky(np.linalg.inv(covs[j]))  # precision = L L^T
        sqrt_precision[j][np.ix_(np.arange(len(kept)), kept)] = chol.T
        log_norm[j] = -2 * np.log(weights[j]) + np.linalg.slogdet(covs[j])[1]
    sqrt_precision = sqrt_precision[:, :len(kept)]
    which = "all genres" if genres == GENRES else ", ".join(genres)
    tmp = Path(args.out).with_name(Path(args.out).stem + ".partial.npz")  # written whole, then renamed
    np.savez_compressed(tmp, means=mean_full, sqrt_precision=sqrt_precision, log_norm=log_norm,
                        weights=weights, kept=kept, genres=np.array(genres),
                        source=np.array(f"hdvr synth, {args.clips_per_genre} clips per genre x {args.seconds} s, "
                                        f"{which}, seed {args.seed}, every {args.every} frames, "
                                        f"{len(hinges)} poses, {k} components, covariance floor "
                                        f"{args.covariance_floor_deg:g} deg"))
    tmp.replace(args.out)
    train = np.logaddexp.reduce(component_loglik(hinges[:, kept], weights, means, covs), axis=1).mean()
    held = ""
    if args.held_out_clips_per_genre > 0:
        other = synthetic_hinges(args.held_out_clips_per_genre, args.seconds, args.seed + 1, args.every, genres)
        held = (f", held out (seed {args.seed + 1}, {len(other)} poses) "
                f"{np.logaddexp.reduce(component_loglik(other[:, kept], weights, means, covs), axis=1).mean():.2f}")
    print(f"{len(hinges)} poses, {k} components, mean log-likelihood {train:.2f}{held}, "
          f"{time.process_time() - clock:.1f} s CPU -> {args.out}")


if __name__ == "__main__":
    main()
