"""Movement vocabulary (16 body parts, 154 labels) and the reference labeller for 3D BODY_25 motion."""

from hdvr.movements.taxonomy import Label, Part, Taxonomy, load_taxonomy

__all__ = ["Label", "Part", "Taxonomy", "load_taxonomy"]
