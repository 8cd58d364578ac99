"""The nine genres of the HDVR paper as choreography styles: tempo, metre, energy and per-group vocabulary.

A style gives, for each motor group (head, neck, trunk, arms, legs), weights of the primitive kinds the
choreography generator composes (see :mod:`hdvr.synth.choreography`), the joint speed range (rad/s), the
fraction of each joint's range used (amplitude), and scene facts (couples, turns, jumps).
"""

from __future__ import annotations

from dataclasses import dataclass, field, replace

from hdvr.errors import HDVRError

GENRES: tuple[str, ...] = ("ballet", "belly_dance", "flamenco", "hip_hop", "rumba", "swing", "tango", "tap", "waltz")
GENRE_DISPLAY = {"ballet": "Ballet", "belly_dance": "Belly dance", "flamenco": "Flamenco", "hip_hop": "Hip Hop",
                 "rumba": "Rumba", "swing": "Swing", "tango": "Tango", "tap": "Tap", "waltz": "Waltz"}


@dataclass(frozen=True)
class GenreStyle:
    """How a genre moves. Weights are relative; missing kinds have weight 0.

    ``bpm``: tempo range (beats per minute); ``beats_per_bar``: metre (3 for waltz); ``speed``: joint speed range of
    directional moves (rad/s); ``amplitude``: fraction of each joint's range used; ``couple``: partner dance;
    ``osc_hz``: frequency range of swings / circles (Hz).
    """

    name: str
    bpm: tuple[float, float]
    beats_per_bar: int
    speed: tuple[float, float]
    amplitude: float
    couple: bool
    osc_hz: tuple[float, float]
    head: dict = field(default_factory=dict)
    neck: dict = field(default_factory=dict)
    trunk: dict = field(default_factory=dict)
    arm: dict = field(default_factory=dict)
    legs: dict = field(default_factory=dict)  # phrases: "gesture", "plie", "relieve", "turn", "hips_*", "hold", "flip"
    gesture: dict = field(default_factory=dict)  # gesture-leg primitives
    symmetric_arms: float = 0.3  # probability that both arms do the same (mirrored) primitive
    walk: float = 0.0  # weight of travelling (walk) phrases among the leg phrases
    step_rad: tuple[float, float] = (0.2, 0.3)  # hip swing of a step each side of vertical (rad)
    curve_rad: float = 0.0  # largest heading change per step of a solo dancer (rad): curved paths
    travel_radius_m: float = 1.0  # paths stay within this distance of the dancer's start (metres)
    turnout_rad: tuple[float, float] = (0.0, 0.0)  # hip external rotation of plies, passes and gestures (rad)
    second_position: float = 0.0  # probability that a plie is done with the feet apart (second position)


def _style(name, bpm, bars, speed, amp, couple, osc, head, neck, trunk, arm, legs, gesture, sym=0.3):
    return GenreStyle(name, bpm, bars, speed, amp, couple, osc, head, neck, trunk, arm, legs, gesture, sym)


STYLES: dict[str, GenreStyle] = {
    "ballet": _style("ballet", (60, 90), 3, (1.0, 2.2), 0.9, False, (1.0, 1.4),
                     {"hold": 4, "move": 3, "circle": 0.3, "jitter": 0.1}, {"hold": 5, "move": 1, "circle": 0.2, "jitter": 0.1},
                     {"hold": 4, "move": 2, "swing": 0.4, "circle": 0.3, "jitter": 0.1},
                     {"hold": 2, "move": 5, "circle": 0.6, "swing": 0.4, "forearm": 0.6, "jitter": 0.1},
                     {"gesture": 5, "relieve": 2, "plie": 2, "turn": 2.5, "hold": 1, "hips_shift": 0.3, "hips_jitter": 0.1},
                     {"move": 4, "kick": 1.5, "circle": 1.5, "swing": 1, "knee": 1, "hold": 1.5, "foot": 2, "jitter": 0.2},
                     sym=0.6),
    "belly_dance": _style("belly_dance", (90, 120), 4, (0.9, 1.8), 0.6, False, (1.0, 1.3),
                          {"hold": 3, "move": 2, "circle": 0.6, "jitter": 0.3}, {"hold": 2, "move": 3, "circle": 1, "jitter": 0.3},
                          {"hold": 2, "move": 1.5, "swing": 1, "circle": 1.2, "jitter": 0.3},
                          {"hold": 3, "move": 4, "circle": 0.5, "swing": 0.3, "forearm": 1, "jitter": 0.2},
                          {"hips_circle": 3, "hips_eight": 3, "hips_wave": 3, "hips_shift": 2, "hips_jitter": 2,
                           "relieve": 1, "plie": 1, "gesture": 1, "turn": 0.8, "hold": 0.5},
                          {"move": 3, "hold": 2, "foot": 2, "knee": 1, "circle": 0.3, "swing": 0.3, "kick": 0.1, "jitter": 0.3}),
    "flamenco": _style("flamenco", (100, 140), 3, (1.4, 2.8), 0.8, False, (1.1, 1.6),
                       {"hold": 3, "move": 4, "circle": 0.2, "jitter": 0.2}, {"hold": 4, "move": 1, "circle": 0.2, "jitter": 0.2},
                       {"hold": 2, "move": 3, "swing": 0.5, "circle": 0.4, "jitter": 0.2},
                       {"hold": 2, "move": 4, "circle": 1.2, "swing": 0.3, "forearm": 1.5, "jitter": 0.2},
                       {"gesture": 4, "turn": 2, "plie": 1, "relieve": 1, "hold": 1, "hips_shift": 0.5, "hips_jitter": 0.2},
                       {"move": 3, "kick": 1.2, "knee": 2, "foot": 3, "swing": 1, "circle": 0.5, "hold": 1, "jitter": 0.5}),
    "hip_hop": _style("hip_hop", (85, 105), 4, (1.5, 3.0), 0.85, False, (1.2, 2.0),
                      {"hold": 2, "move": 5, "circle": 0.5, "jitter": 0.6}, {"hold": 2, "move": 2, "circle": 0.5, "jitter": 0.5},
                      {"hold": 2, "move": 4, "swing": 1, "circle": 0.6, "jitter": 0.8},
                      {"hold": 1.5, "move": 5, "circle": 0.7, "swing": 1.5, "forearm": 1, "jitter": 0.8},
                      {"gesture": 3, "plie": 3, "relieve": 1, "turn": 1, "flip": 1.2, "hips_shift": 1, "hips_wave": 0.5,
                       "hips_jitter": 0.6, "hold": 1},
                      {"move": 4, "kick": 1.5, "knee": 1.5, "swing": 1, "circle": 0.5, "foot": 1.5, "hold": 1, "jitter": 0.8}),
    "rumba": _style("rumba", (100, 110), 4, (0.9, 1.8), 0.7, True, (1.0, 1.3),
                    {"hold": 4, "move": 3, "circle": 0.2, "jitter": 0.1}, {"hold": 4, "move": 1, "circle": 0.2, "jitter": 0.1},
                    {"hold": 3, "move": 2, "swing": 0.6, "circle": 0.6, "jitter": 0.1},
                    {"hold": 2, "move": 4, "circle": 0.4, "swing": 0.5, "forearm": 0.6, "jitter": 0.1},
                    {"hips_eight": 2.5, "hips_wave": 2, "hips_circle": 1, "hips_shift": 2, "gesture": 3, "turn": 1.2,
                     "plie": 1, "relieve": 0.5, "hold": 1, "hips_jitter": 0.2},
                    {"move": 4, "swing": 0.8, "circle": 0.5, "knee": 1, "foot": 1.5, "hold": 1.5, "kick": 0.3, "jitter": 0.2},
                    sym=0.4),
    "swing": _style("swing", (130, 180), 4, (1.6, 3.0), 0.8, True, (1.4, 2.2),
                    {"hold": 3, "move": 3, "circle": 0.2, "jitter": 0.2}, {"hold": 3, "move": 1, "circle": 0.2, "jitter": 0.2},
                    {"hold": 3, "move": 2, "swing": 1.2, "circle": 0.3, "jitter": 0.2},
                    {"hold": 2, "move": 3, "circle": 0.3, "swing": 2, "forearm": 0.6, "jitter": 0.2},
                    {"gesture": 5, "turn": 1.5, "plie": 1.5, "relieve": 0.5, "hips_wave": 0.5, "hold": 1, "hips_jitter": 0.2},
                    {"kick": 2.5, "swing": 2, "move": 3, "knee": 1.5, "circle": 0.4, "foot": 1, "hold": 1, "jitter": 0.3}),
    "tango": _style("tango", (110, 130), 4, (1.2, 2.6), 0.75, True, (1.0, 1.5),
                    {"hold": 3, "move": 4, "circle": 0.1, "jitter": 0.1}, {"hold": 4, "move": 1, "circle": 0.1, "jitter": 0.1},
                    {"hold": 4, "move": 2.5, "swing": 0.4, "circle": 0.2, "jitter": 0.1},
                    {"hold": 4, "move": 2, "circle": 0.2, "swing": 0.3, "forearm": 0.5, "jitter": 0.1},
                    {"gesture": 5, "turn": 1.5, "plie": 1.2, "relieve": 0.4, "hold": 1, "hips_shift": 0.6, "hips_jitter": 0.1},
                    {"move": 3, "knee": 2.5, "swing": 1, "circle": 1, "kick": 1, "foot": 1.2, "hold": 1.5, "jitter": 0.2}),
    "tap": _style("tap", (120, 160), 4, (1.6, 3.0), 0.6, False, (1.6, 2.3),
                  {"hold": 4, "move": 2, "circle": 0.1, "jitter": 0.2}, {"hold": 4, "move": 1, "circle": 0.1, "jitter": 0.2},
                  {"hold": 4, "move": 1.5, "swing": 0.5, "circle": 0.2, "jitter": 0.2},
                  {"hold": 2, "move": 2, "circle": 0.2, "swing": 2, "forearm": 0.5, "jitter": 0.2},
                  {"gesture": 6, "plie": 1, "relieve": 1, "turn": 0.6, "hold": 0.5, "hips_jitter": 0.3},
                  {"foot": 5, "knee": 3, "swing": 1.5, "move": 2, "kick": 0.8, "hold": 0.7, "circle": 0.3, "jitter": 1}),
    "waltz": _style("waltz", (84, 96), 3, (0.9, 1.8), 0.6, True, (1.0, 1.3),
                    {"hold": 4, "move": 2, "circle": 0.1, "jitter": 0.05}, {"hold": 4, "move": 1, "circle": 0.1, "jitter": 0.05},
                    {"hold": 4, "move": 2, "swing": 0.5, "circle": 0.2, "jitter": 0.05},
                    {"hold": 4, "move": 2, "circle": 0.2, "swing": 0.3, "forearm": 0.3, "jitter": 0.05},
                    {"turn": 3, "relieve": 2.5, "plie": 2.5, "gesture": 2.5, "hold": 0.8, "hips_shift": 0.5, "hips_jitter": 0.05},
                    {"move": 4, "swing": 1, "circle": 0.6, "knee": 0.8, "foot": 1, "hold": 1.5, "kick": 0.2, "jitter": 0.1},
                    sym=0.5),
}


#: Floor paths per genre (walk weight, step size, curvature, radius): waltz travels on curves (line of dance,
#: rotating), tango walks straight promenades, ballet crosses on diagonals, swing / rumba / flamenco travel a
#: little, belly dance less, hip hop and tap stay mostly in place.
TRAVEL = {"ballet": (2.5, (0.3, 0.4), 0.05, 2.2), "belly_dance": (0.5, (0.15, 0.25), 0.2, 0.8),
          "flamenco": (1.0, (0.2, 0.3), 0.2, 1.2), "hip_hop": (0.4, (0.15, 0.25), 0.2, 0.6),
          "rumba": (2.5, (0.2, 0.3), 0.0, 1.2), "swing": (2.5, (0.2, 0.3), 0.0, 1.2),
          "tango": (5.0, (0.3, 0.4), 0.0, 2.0), "tap": (0.4, (0.15, 0.2), 0.15, 0.6),
          "waltz": (6.0, (0.25, 0.35), 0.0, 2.0)}
for _name, (_w, _step, _curve, _radius) in TRAVEL.items():
    STYLES[_name] = replace(STYLES[_name], walk=_w, step_rad=_step, curve_rad=_curve, travel_radius_m=_radius)


#: Turnout per genre: range of the hip's external rotation in plies, passes and leg gestures (rad; the knee points
#: this far out from straight ahead) and the probability of a plie in second position (feet apart, legs abducted
#: 0.12-0.3 rad). Ballet is danced turned out (about 40-60 deg at the hip; the rest of the feet's 90 deg comes from
#: knees and ankles); hip hop squats wide with the knees out; belly dance and flamenco bend the knees a little out;
#: the ballroom and partner dances stay near parallel.
TURNOUT = {"ballet": ((0.6, 1.0), 0.4), "belly_dance": ((0.0, 0.4), 0.3), "flamenco": ((0.2, 0.6), 0.2),
           "hip_hop": ((0.0, 0.7), 0.5), "rumba": ((0.0, 0.3), 0.1), "swing": ((0.0, 0.3), 0.2),
           "tango": ((0.0, 0.3), 0.1), "tap": ((0.0, 0.4), 0.2), "waltz": ((0.0, 0.2), 0.05)}
for _name, (_turnout, _second) in TURNOUT.items():
    STYLES[_name] = replace(STYLES[_name], turnout_rad=_turnout, second_position=_second)


def genre_style(name: str) -> GenreStyle:
    key = name.strip().lower().replace(" ", "_").replace("-", "_")
    if key not in STYLES:
        raise HDVRError(f"unknown genre {name!r}; choose from {', '.join(GENRES)}")
    return STYLES[key]


def parse_genres(text: str | None) -> tuple[str, ...]:
    """``"ballet,tango"`` -> ("ballet", "tango"); None or ``all`` -> all nine."""
    if text is None or text.strip().lower() in ("", "all"):
        return GENRES
    return tuple(genre_style(g).name for g in text.split(","))
