"""The movement vocabulary: 16 body parts and 154 labels, read from ``hdvr/data/movements.json``.

Each label has a global id (0..153, in file order) and a per-part index. Label kinds (how the labeller decides):

- ``direction``: the part moves and its dominant velocity component is ``component`` with sign ``sign``.
- ``fast``: direction speed above the kick threshold (legs: Kicking).
- ``turning``: pelvis heading turns faster than the turn threshold (hips).
- ``pattern``: windowed shape of the motion (``circle``, ``oscillation``, ``figure8``; ``a|b`` accepts either).
- ``somersault``: the trunk flips in the world's vertical plane (torso).
- ``hold``: still with a posture condition (``high``, ``forward``, ``backward``, ``side``).
- ``state``: foot posture (``extension``, ``flexion``, ``relaxed``).
- ``still``: none of the above while not moving; ``unknown``: missing data or motion no label names.
"""

from __future__ import annotations

import json
from dataclasses import dataclass
from functools import lru_cache
from pathlib import Path

from hdvr.errors import HDVRError

TAXONOMY_PATH = Path(__file__).resolve().parents[1] / "data" / "movements.json"
NUM_PARTS = 16
NUM_LABELS = 154


@dataclass(frozen=True)
class Label:
    """One movement label of one body part."""

    id: int  # global id 0..153
    index: int  # index within its part
    part: str
    name: str
    kind: str
    definition: str
    component: str | None = None
    sign: int = 0
    pattern: str | None = None
    condition: str | None = None
    paper_name: str | None = None

    @property
    def key(self) -> str:
        """Unique name, ``part:name`` (``Unknown`` occurs in several parts)."""
        return f"{self.part}:{self.name}"


@dataclass(frozen=True)
class Part:
    """A body part: its measure (how the labeller reads it from BODY_25), motion components and labels."""

    index: int
    name: str
    display: str
    measure: str
    side: str | None
    motion_components: tuple[str, ...]
    labels: tuple[Label, ...]

    def label(self, name_or_kind: str) -> Label:
        """The label with this exact name, or the first of this kind (``still``, ``unknown``, ...)."""
        for lab in self.labels:
            if lab.name == name_or_kind:
                return lab
        for lab in self.labels:
            if lab.kind == name_or_kind:
                return lab
        raise HDVRError(f"body part {self.name} has no label or kind {name_or_kind!r}")

    def find(self, kind: str, **attrs) -> Label | None:
        """First label of ``kind`` whose attributes equal ``attrs`` (pattern matches any of ``a|b``)."""
        for lab in self.labels:
            if lab.kind != kind:
                continue
            ok = True
            for k, v in attrs.items():
                have = getattr(lab, k)
                if k == "pattern":
                    ok &= have is not None and v in have.split("|")
                else:
                    ok &= have == v
            if ok:
                return lab
        return None


@dataclass(frozen=True)
class Taxonomy:
    parts: tuple[Part, ...]
    labels: tuple[Label, ...]
    thresholds: dict

    def part(self, name: str) -> Part:
        for p in self.parts:
            if p.name == name:
                return p
        raise HDVRError(f"unknown body part {name!r}; known: {[p.name for p in self.parts]}")

    @property
    def part_names(self) -> tuple[str, ...]:
        return tuple(p.name for p in self.parts)


def _parse(doc: dict, source: str) -> Taxonomy:
    try:
        parts, labels = [], []
        for pi, p in enumerate(doc["parts"]):
            plabels = []
            for li, lab in enumerate(p["labels"]):
                label = Label(len(labels), li, p["name"], lab["name"], lab["kind"], lab["definition"],
                              lab.get("component"), int(lab.get("sign", 0)), lab.get("pattern"),
                              lab.get("condition"), lab.get("paper_name"))
                labels.append(label)
                plabels.append(label)
            parts.append(Part(pi, p["name"], p["display"], p["measure"], p.get("side"),
                              tuple(p["motion_components"]), tuple(plabels)))
        tax = Taxonomy(tuple(parts), tuple(labels), dict(doc["thresholds"]))
    except (KeyError, TypeError) as exc:
        raise HDVRError(f"malformed movement taxonomy {source}: missing or bad field {exc}") from None
    if len(tax.parts) != NUM_PARTS or len(tax.labels) != NUM_LABELS:
        raise HDVRError(f"movement taxonomy {source} has {len(tax.parts)} parts / {len(tax.labels)} labels, "
                        f"expected {NUM_PARTS} / {NUM_LABELS}")
    return tax


@lru_cache(maxsize=4)
def load_taxonomy(path: str | None = None) -> Taxonomy:
    """Read the vocabulary (default: the packaged ``movements.json``)."""
    p = Path(path) if path else TAXONOMY_PATH
    if not p.is_file():
        raise HDVRError(f"movement taxonomy not found: {p}")
    try:
        doc = json.loads(p.read_text(encoding="utf-8"))
    except json.JSONDecodeError as exc:
        raise HDVRError(f"movement taxonomy {p} is not valid JSON: {exc.msg} at line {exc.lineno}") from None
    return _parse(doc, str(p))
