"""A Labanotation-like score of movement labels: one column per body part, time running upward.

Columns follow the Labanotation staff layout: the body's left side on the left, the right side on the right,
the trunk, hips and head in the middle (left foot, left lower/upper leg, hips, torso, left shoulder/arms,
head and neck, then the mirror for the right). Each label segment is a block coloured by its movement family
(up / down / left / right / forward / backward / circling / swinging / turning / still / hold / unknown) with
its short name written in when it fits.
"""

from __future__ import annotations

import os

import numpy as np

from hdvr.movements.labeller import Labels

COLUMN_ORDER = ("left_foot", "left_lower_leg", "left_upper_leg", "left_lower_arm", "left_upper_arm",
                "left_shoulder", "hips", "torso", "neck", "head", "right_shoulder", "right_upper_arm",
                "right_lower_arm", "right_upper_leg", "right_lower_leg", "right_foot")

FAMILY_COLOURS = {
    "Upward": "#d62728", "Up": "#d62728", "Downward": "#1f77b4", "Down": "#1f77b4", "Left": "#2ca02c",
    "Right": "#ff7f0e", "Forward": "#9467bd", "Backward": "#8c564b", "Circling": "#e377c2", "Swinging": "#17becf",
    "Swing": "#17becf", "Waving": "#17becf", "Figure 8": "#bcbd22", "Turning": "#7f7f7f", "Kicking": "#ff0000",
    "Bending": "#9467bd", "Unbending": "#8c564b", "Somersault": "#000000", "Extension": "#d62728",
    "Flexion": "#1f77b4", "Relaxed": "#dddddd", "Still": "#f4f4f4", "Holding": "#bbbbbb", "Unknown": "#ffffff",
}


def short_name(label: str, part_display: str) -> str:
    """'Left Upper Arm Moving Upward' -> 'Upward'; 'Head Keeping Still' -> 'Still'."""
    s = label[len(part_display) + 1:] if label.startswith(part_display + " ") else label
    if s.startswith("Leaning "):
        return "Lean " + s[len("Leaning "):]
    for prefix in ("Moving ", "Keeping ", "Turning "):
        if s.startswith(prefix):
            return s[len(prefix):]
    return s


def family_colour(short: str) -> str:
    if short.startswith("Holding"):
        return FAMILY_COLOURS["Holding"]
    if short.startswith("Lean "):
        return FAMILY_COLOURS[short[5:]]
    return FAMILY_COLOURS.get(short, "#cccccc")


def draw_score(labels: Labels, path: str | os.PathLike, title: str = "", start_s: float = 0.0,
               end_s: float | None = None, dpi: int = 110) -> None:
    """Write the score of ``labels`` between ``start_s`` and ``end_s`` (seconds) to an image file (PNG/JPEG)."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib.patches import Patch, Rectangle

    from hdvr.io.atomic import atomic_path

    tax = labels.taxonomy
    fps = labels.fps
    T = labels.ids.shape[0]
    end_s = T / fps if end_s is None else min(end_s, T / fps)
    f0, f1 = int(start_s * fps), int(np.ceil(end_s * fps))
    height = max(6.0, min(22.0, (end_s - start_s) * 0.9 + 2))
    fig, ax = plt.subplots(figsize=(13, height))
    for col, pname in enumerate(COLUMN_ORDER):
        part = tax.part(pname)
        for seg in labels.segments():
            if seg["part"] != pname or seg["end"] <= f0 or seg["start"] >= f1:
                continue
            s, e = max(seg["start"], f0) / fps, min(seg["end"], f1) / fps
            short = short_name(seg["label"], part.display)
            ax.add_patch(Rectangle((col + 0.05, s), 0.9, e - s, facecolor=family_colour(short), edgecolor="#444444",
                                   linewidth=0.4))
            if (e - s) * fps >= 6:
                ax.text(col + 0.5, (s + e) / 2, short, ha="center", va="center", fontsize=6, rotation=90,
                        clip_on=True)
    ax.set_xlim(0, len(COLUMN_ORDER))
    ax.set_ylim(start_s, end_s)
    ax.set_xticks(np.arange(len(COLUMN_ORDER)) + 0.5)
    ax.set_xticklabels([tax.part(p).display.replace(" ", "\n", 1) for p in COLUMN_ORDER], fontsize=7)
    ax.set_ylabel("time (s), upward as in Labanotation")
    ax.axvline(len(COLUMN_ORDER) / 2, color="black", linewidth=1.2)  # the staff's centre line
    families = ["Up", "Down", "Left", "Right", "Forward", "Backward", "Circling", "Swinging", "Figure 8", "Turning",
                "Kicking", "Somersault", "Extension", "Flexion", "Relaxed", "Still", "Holding", "Unknown"]
    ax.legend(handles=[Patch(facecolor=family_colour(f), edgecolor="#444444", label=f) for f in families],
              loc="upper center", bbox_to_anchor=(0.5, -0.06), ncol=9, fontsize=7, frameon=False)
    ax.set_title(title or "Movement score", fontsize=10)
    fig.tight_layout()
    suffix = os.path.splitext(str(path))[1] or ".png"
    with atomic_path(path, suffix=suffix) as tmp:
        fig.savefig(tmp, dpi=dpi)
    plt.close(fig)
