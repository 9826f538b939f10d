"""User profiles: a person's traits drawn from seeded distributions.

``humans/profiles.xml`` names populations (typical, cooperative, impatient,
vague, distracted, silent); each gives, per trait, a distribution with
declared bounds. :func:`draw_traits` draws a person's :class:`Traits` from
the run's generator for her (``sim.rng("human:<name>")``), always every
trait in the same order, so the same seed gives the same person and a trait
given in the scenario (``<human voice="65">``) replaces its draw without
changing the others. A person without a profile gets the defaults below and
her scenario's values: nothing is drawn, so scripted scenarios replay as
before.

Traits (docs/users.md gives the sources): ``voice`` (dB SPL at 1 m),
``distance`` (where she stops when she walks up to the robot, m), ``speed``
(m/s, her walking speed when a walk-to gives none), ``patience`` (repairs
before she gives up), ``off_axis`` (probability that she speaks without
facing the robot), ``pointing_error`` (standard deviation of her pointing
direction, degrees), ``phrasing`` (weights of the paraphrase styles),
``repairs`` (the repair strategies she uses), ``give_up`` (what she does
when her patience is used up) and ``mistakes`` (how often she is wrong: says
yes to a wrong guess of the robot's, ``confirm``; names a room or a thing
wrongly when she teaches it, ``misname``; and then corrects herself at once,
``self-correct``: probabilities per occasion, drawn as she goes). Nothing here reaches the robot: it hears her
words and sees her body through its sensor models only.
"""

from __future__ import annotations

from dataclasses import dataclass, field, replace
from functools import lru_cache
from pathlib import Path

import numpy as np

from homesim.errors import InputError
from homesim.scenario.model import GIVE_UPS, REPAIR_STRATEGIES, HumanSpec
from homesim.xmlio import parse_file

from .phrasings import STYLES

PROFILES_PATH = Path(__file__).with_name("profiles.xml")

#: Numeric traits and the range any value of them must lie in (as scenario.xsd's <human> attributes).
NUMERIC: dict[str, tuple[float, float]] = {
    "voice": (30.0, 90.0),
    "distance": (0.3, 5.0),
    "speed": (0.1, 3.0),
    "patience": (0.0, 10.0),
    "off-axis": (0.0, 1.0),
    "pointing-error": (0.0, 45.0),
}
#: Every trait, in draw order.
TRAITS = ("voice", "distance", "speed", "patience", "off-axis", "pointing-error", "phrasing", "repairs", "give-up", "mistakes")
#: What a user can get wrong (``<mistakes confirm= misname= self-correct=/>``: probabilities per occasion).
MISTAKES = ("confirm", "misname", "self-correct")


@dataclass(frozen=True)
class Traits:
    """One person's traits (defaults: the scripted person of a scenario without a profile)."""

    voice: float = 60.0  # conversational speech, dB SPL at 1 m
    distance: float = 0.9  # where she stops in front of the robot (Hall's personal zone)
    speed: float | None = None  # None: the scenario's speed= (1.0 m/s by default)
    patience: int = 2
    off_axis: float = 0.0
    pointing_error: float = 0.0
    phrasing: tuple[tuple[str, float], ...] = ()  # style weights; (): every phrasing alike
    repairs: tuple[str, ...] = ()
    give_up: str = "skip"
    profile: str | None = None
    #: whether her wait-fors repair her way (a profile, or patience/repairs/give-up given on her)
    repairing: bool = False
    #: whether she walks up to the robot face to face at her distance (a profile, or distance= given)
    approach: bool = False
    #: how often she is wrong (probabilities per occasion): says yes to a wrong guess of the robot's,
    #: names a room or a thing she teaches wrongly, corrects such a slip of hers at once
    confirm_wrongly: float = 0.0
    misname: float = 0.0
    self_correct: float = 0.0


@dataclass(frozen=True)
class Dist:
    """A distribution of one numeric trait with its declared bounds."""

    kind: str  # normal | uniform | choice | fixed
    params: tuple[float, ...]
    low: float
    high: float
    weights: tuple[float, ...] = ()
    line: int | None = None

    def draw(self, rng: np.random.Generator) -> float:
        """One value in [low, high] (one draw from ``rng`` whatever the kind, so draw order is stable)."""
        u = float(rng.random())
        if self.kind == "fixed":
            return self.params[0]
        if self.kind == "uniform":
            return self.low + u * (self.high - self.low)
        if self.kind == "choice":
            cum = np.cumsum(self.weights) / sum(self.weights)
            return self.params[int(min(np.searchsorted(cum, u, side="right"), len(self.params) - 1))]
        mean, sd = self.params
        if sd <= 0:
            return min(max(mean, self.low), self.high)
        from scipy.special import ndtr, ndtri  # only a generated user draws: not on every run's start

        # truncated to [low, high] by the inverse CDF (not clipped: a clipped draw piles a share of
        # the users exactly on a bound; still one draw from rng)
        a, b = float(ndtr((self.low - mean) / sd)), float(ndtr((self.high - mean) / sd))
        p = a + u * (b - a)
        v = mean + sd * float(ndtri(min(max(p, 1e-12), 1 - 1e-12)))
        return min(max(v, self.low), self.high)


@dataclass(frozen=True)
class Profile:
    name: str
    description: str
    numeric: dict[str, Dist]
    phrasing: tuple[tuple[str, float], ...]
    repairs: tuple[tuple[str, float], ...]
    give_up: tuple[tuple[str, float], ...]
    line: int | None = None
    extra: dict[str, str] = field(default_factory=dict)
    mistakes: tuple[tuple[str, float], ...] = ()


def _floats(raw: str, what: str, source: str, line: int | None) -> tuple[float, ...]:
    try:
        vals = tuple(float(v) for v in raw.split())
    except ValueError:
        raise InputError(f"{what}={raw!r}: not numbers", source=source, line=line) from None
    if not all(np.isfinite(vals)):
        raise InputError(f"{what}={raw!r}: not finite numbers", source=source, line=line)
    return vals


def _dist(el, trait: str, source: str) -> Dist:  # type: ignore[no-untyped-def]
    lo_ok, hi_ok = NUMERIC[trait]
    line = el.sourceline
    kinds = [k for k in ("normal", "uniform", "choice", "fixed") if el.get(k) is not None]
    if len(kinds) != 1:
        raise InputError(f"<{trait}> needs exactly one of normal=, uniform=, choice=, fixed=", source=source, line=line)
    kind = kinds[0]
    params = _floats(el.get(kind), kind, source, line)
    weights: tuple[float, ...] = ()
    if kind == "normal":
        if len(params) != 2 or params[1] < 0:
            raise InputError(f"normal={el.get(kind)!r}: 'mean sd' with sd >= 0", source=source, line=line)
        if el.get("min") is None or el.get("max") is None:
            raise InputError(f"<{trait} normal=...> needs min= and max= (its declared bounds)", source=source, line=line)
        low, high = _floats(el.get("min"), "min", source, line)[0], _floats(el.get("max"), "max", source, line)[0]
    elif kind == "uniform":
        if len(params) != 2:
            raise InputError(f"uniform={el.get(kind)!r}: 'low high'", source=source, line=line)
        low, high = params
    elif kind == "choice":
        if not params:
            raise InputError("choice= needs values", source=source, line=line)
        weights = _floats(el.get("weights"), "weights", source, line) if el.get("weights") else (1.0,) * len(params)
        if len(weights) != len(params) or min(weights) < 0 or sum(weights) <= 0:
            raise InputError("weights= needs one non-negative weight per value, not all zero", source=source, line=line)
        low, high = min(params), max(params)
    else:
        if len(params) != 1:
            raise InputError(f"fixed={el.get(kind)!r}: one value", source=source, line=line)
        low = high = params[0]
    if not (lo_ok <= low <= high <= hi_ok):
        raise InputError(f"<{trait}> bounds {low:g} to {high:g} must lie in {lo_ok:g} to {hi_ok:g} (low <= high)", source=source, line=line)
    if trait == "patience" and (any(v != int(v) for v in params if kind in ("choice", "fixed")) or low != int(low) or high != int(high)):
        # a draw is rounded to a whole number of repairs: bounds between whole numbers would not hold it
        raise InputError("patience counts repairs: whole numbers (and whole bounds)", source=source, line=line)
    return Dist(kind, params, low, high, weights, line)


def _weights(el, allowed: tuple[str, ...], what: str, source: str) -> tuple[tuple[str, float], ...]:  # type: ignore[no-untyped-def]
    if el is None:
        return ()
    out = []
    for k, v in el.attrib.items():
        if k not in allowed:
            raise InputError(f"<{what}> {k}=: one of {', '.join(allowed)}", source=source, line=el.sourceline)
        w = _floats(v, k, source, el.sourceline)
        if len(w) != 1 or not 0 <= w[0]:
            raise InputError(f"<{what}> {k}={v!r}: one number >= 0", source=source, line=el.sourceline)
        out.append((k, w[0]))
    return tuple(sorted(out, key=lambda kv: allowed.index(kv[0])))


def load_profiles(path: str | Path = PROFILES_PATH) -> dict[str, Profile]:
    """Read a profiles file; InputError naming file and line for a bad entry."""
    source = str(path)
    root = parse_file(path)
    if root.tag != "profiles":
        raise InputError(f"root element <{root.tag}> is not <profiles>", source=source, line=root.sourceline)
    out: dict[str, Profile] = {}
    for p in root.iterfind("profile"):
        name = p.get("name")
        if not name or name in out:
            raise InputError(f"profile name {name!r} missing or given twice", source=source, line=p.sourceline)
        numeric = {}
        for trait in NUMERIC:
            el = p.find(trait)
            if el is None:
                raise InputError(f"profile {name!r} has no <{trait}>", source=source, line=p.sourceline)
            numeric[trait] = _dist(el, trait, source)
        given: dict[str, int | None] = {}
        for child in p:
            if isinstance(child.tag, str) and child.tag not in TRAITS:
                raise InputError(f"<{child.tag}> is not a trait; traits: {', '.join(TRAITS)}", source=source, line=child.sourceline)
            if isinstance(child.tag, str) and child.tag in given:
                # only the first would count: the second would be silently ignored
                raise InputError(f"profile {name!r} gives <{child.tag}> twice (first at line {given[child.tag]})", source=source, line=child.sourceline)
            if isinstance(child.tag, str):
                given[child.tag] = child.sourceline
        give_up = _weights(p.find("give-up"), GIVE_UPS, "give-up", source)
        if not give_up or sum(w for _, w in give_up) <= 0:
            raise InputError(f"profile {name!r}: <give-up> needs a positive weight", source=source, line=p.sourceline)
        phrasing_el = p.find("phrasing")
        if phrasing_el is not None and sum(w for _, w in _weights(phrasing_el, STYLES, "phrasing", source)) <= 0:
            # all zero: every style was silently drawn alike, the opposite of what the weights say
            raise InputError(f"profile {name!r}: <phrasing> needs a positive weight (or leave it out: all styles alike)",
                             source=source, line=phrasing_el.sourceline)
        repairs = _weights(p.find("repairs"), REPAIR_STRATEGIES, "repairs", source)
        if any(w > 1 for _, w in repairs):
            raise InputError(f"profile {name!r}: <repairs> gives probabilities (0 to 1)", source=source, line=p.sourceline)
        mistakes = _weights(p.find("mistakes"), MISTAKES, "mistakes", source)
        if any(w > 1 for _, w in mistakes):
            raise InputError(f"profile {name!r}: <mistakes> gives probabilities (0 to 1)", source=source, line=p.find("mistakes").sourceline)
        out[name] = Profile(name, p.get("description", ""), numeric, _weights(p.find("phrasing"), STYLES, "phrasing", source),
                            repairs, give_up, p.sourceline, mistakes=mistakes)
    return out


@lru_cache(maxsize=1)
def default_profiles() -> dict[str, Profile]:
    """The profiles shipped in ``humans/profiles.xml`` (read once per process)."""
    return load_profiles(PROFILES_PATH)


def draw_profile(profile: Profile, rng: np.random.Generator) -> Traits:
    """Every trait of ``profile`` drawn from ``rng``, in :data:`TRAITS` order."""
    n = profile.numeric
    values = {k: n[k].draw(rng) for k in NUMERIC}
    repairs = tuple(s for s, p in profile.repairs if float(rng.random()) < p)
    # the repairs draw consumes one number per strategy whatever the profile lists, for a stable order
    for _ in range(len(REPAIR_STRATEGIES) - len(profile.repairs)):
        rng.random()
    w = np.array([x for _, x in profile.give_up])
    u = float(rng.random())
    k = int(min(np.searchsorted(np.cumsum(w) / w.sum(), u, side="right"), len(w) - 1))
    return Traits(voice=values["voice"], distance=values["distance"], speed=values["speed"], patience=int(round(values["patience"])),
                  off_axis=values["off-axis"], pointing_error=values["pointing-error"], phrasing=profile.phrasing,
                  repairs=repairs, give_up=profile.give_up[k][0], profile=profile.name, repairing=True, approach=True,
                  # probabilities, not draws: each occasion draws as she goes (no draw here, so adding
                  # mistakes to a profile leaves every other trait's draw as it was)
                  confirm_wrongly=dict(profile.mistakes).get("confirm", 0.0), misname=dict(profile.mistakes).get("misname", 0.0),
                  self_correct=dict(profile.mistakes).get("self-correct", 0.0))


def apply_overrides(traits: Traits, given: tuple[tuple[str, str], ...]) -> Traits:
    """The traits with the values a scenario gives for this person (as written) put in."""
    changes: dict[str, object] = {}
    for key, raw in given:
        if key in ("patience", "repairs", "give-up"):
            changes["repairing"] = True
        if key == "voice":
            changes["voice"] = float(raw)
        elif key == "distance":
            changes["distance"] = float(raw)
            changes["approach"] = True
        elif key == "speed":
            changes["speed"] = float(raw)
        elif key == "patience":
            changes["patience"] = int(raw)
        elif key == "off-axis":
            changes["off_axis"] = float(raw)
        elif key == "pointing-error":
            changes["pointing_error"] = float(raw)
        elif key == "phrasing":
            changes["phrasing"] = ((raw, 1.0),)
        elif key == "repairs":
            changes["repairs"] = () if raw == "none" else tuple(raw.split())
        elif key == "give-up":
            changes["give_up"] = raw
    return replace(traits, **changes)  # type: ignore[arg-type]


def traits_for(spec: HumanSpec, rng: np.random.Generator | None) -> Traits:
    """A person's traits: her profile's draws (from ``rng``) with her scenario's values put in.

    Without a profile nothing is drawn (``rng`` may be None).
    """
    base = Traits()
    if spec.profile is not None:
        if rng is None:
            raise ValueError(f"{spec.name!r} has profile {spec.profile!r}: her traits need a generator")
        base = draw_profile(default_profiles()[spec.profile], rng)
    return apply_overrides(base, spec.traits)


def _check_profiles_file(path: str) -> list[InputError]:
    try:
        load_profiles(path)
    except InputError as exc:
        return [exc]
    return []


def _check_bank_file(path: str) -> list[InputError]:
    from .phrasings import load_bank

    try:
        load_bank(path)
    except InputError as exc:
        return [exc]
    return []


def _document_types():  # type: ignore[no-untyped-def]
    from homesim.check import DocumentType

    return DocumentType("profiles", "user profiles", _check_profiles_file), DocumentType("phrasings", "paraphrase bank", _check_bank_file)


#: ``homesim check humans/profiles.xml`` / ``humans/phrasings.xml`` (entry points in pyproject.toml).
PROFILES_DOCUMENT, BANK_DOCUMENT = _document_types()
