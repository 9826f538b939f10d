"""BIRON's knowledge bases: objects and places, each an active memory.

The bases give the documents their meaning; :mod:`homesim.memory` only stores
them. Each base turns what the modules send (speech frames, object
attention's ``OBJECT``, the ES's ``POSE``) into one canonical document,
checked against ``robot/schemas/knowledge.xsd`` before it is stored:

``<OBJECT type name owner use colour x y z size frame="map" taught><ATTRIBUTE name/>*<POSITION relation landmark/>?</OBJECT>``
(``owner="partner"``: the person who was talking to the robot, whatever word the frame used)
(visual features, e.g. a colour histogram, are binary attachments of the
document, never inline XML), and ``<PLACE name x y theta frame="map" taught/>``.

Objects are indexed by type, name and owner, places by name, so the common
look-ups stay fast as the memory grows. Teaching the same thing again
updates it (a place by name; an object by type, name and owner when these
single it out, else by type and name within :data:`SAME_OBJECT` metres with no
contradicting owner, :data:`SAME_SPOT` when only one of the two says an owner; never one of
another colour), keeping what the new teaching does not say (owner,
attributes: :meth:`ObjectBase.merged`), so a correction never leaves a duplicate.

How it fails: a document that cannot be made canonical (no type, no
position, no pose, a number that does not read) raises
:class:`MemoryQueryError` saying what is missing; nothing is stored. A
document read back from the store is checked the same way (its base's tag,
the schema) before anything uses it: a bad one stops the run at the start with
:class:`MemoryStoreError` naming the store file and the document.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from copy import deepcopy
from pathlib import Path

from lxml import etree

from homesim.errors import MemoryQueryError
from homesim.memory.core import ActiveMemory, Attachment, Record
from homesim.memory.protocol import decode_inline
from homesim.memory.sqlite import SqliteStore
from homesim.xmlio import load_schema

from .where import TaughtPlace

SCHEMA = Path(__file__).resolve().parent.parent / "schemas" / "knowledge.xsd"
SAME_OBJECT = 0.5
#: metres: a teaching that says an owner where the stored one has none (or the other way round) is
#: the same object taught again only this close: the object attention's own resolution
#: (robot/objects/resolve.py MERGE: detections further apart are two objects), well above how far a
#: cup re-taught from where she stands moves in the robot's estimate (a few cm). Further away, the
#: missing "my" is no reason to take another cup beside hers for hers.
SAME_SPOT = 0.2

OBJECT_INDEXES = {"type": "@type", "name": "@name", "owner": "@owner"}
PLACE_INDEXES = {"name": "@name"}
#: metres: a place named again within this distance of where a wrong name was just given is that place
SAME_PLACE = 1.5


def _clean(text: str | None) -> str:
    return " ".join((text or "").lower().split())


def _child_name(el: etree._Element, tag: str) -> str:
    c = el.find(tag)
    return _clean(c.get("name")) if c is not None else ""


def _number(el: etree._Element, attr: str, what: str) -> float:
    text = el.get(attr)
    try:
        v = float(text)  # type: ignore[arg-type]
    except (TypeError, ValueError):
        raise MemoryQueryError(f"{what} needs a number {attr}=, got {text!r}", source="<knowledge>", element=el.tag) from None
    if not math.isfinite(v):
        raise MemoryQueryError(f"{what}: {attr}={text!r} is not finite", source="<knowledge>", element=el.tag)
    return v


def _fmt(v: float) -> str:
    return f"{v:.4f}"


#: Words for "the person talking to the robot": the speech frame says "speaker" for "my", the
#: object attention "partner"; both are stored and matched as "partner".
PARTNER_WORDS = frozenset({"partner", "speaker", "my", "me", "mine", "i"})


def owner_of(el: etree._Element) -> str:
    """The owner as stored: lower case, any word for the partner as "partner"."""
    owner = _clean(el.get("owner")) or _child_name(el, "OWNER")
    return "partner" if owner in PARTNER_WORDS else owner


def describe(el: etree._Element) -> dict[str, str]:
    """type, name, owner, colour, use of an OBJECT given as attributes or speech-frame children."""
    out = {
        "type": _clean(el.get("type")),
        "name": _clean(el.get("name")) or _child_name(el, "TITLE"),
        "owner": owner_of(el),
        "colour": _clean(el.get("colour")) or _child_name(el, "COLOUR"),
        "use": _clean(el.get("use")) or _child_name(el, "USE"),
    }
    return out


def said_position(el: etree._Element) -> tuple[str, str] | None:
    """(relation, landmark) of ``POSITION`` as stored or as a speech frame has it; None without one."""
    pos = el.find("POSITION")
    if pos is None:
        return None
    rel = _clean(pos.get("relation")) or _child_name(pos, "RELATION")
    landmark = _clean(pos.get("landmark")) or _child_name(pos, "TITLE")
    return (rel or "near", landmark) if landmark else None


class KnowledgeBase:
    """One base: an active memory, its indexes and the canonical form of its documents."""

    kind = ""
    tag = ""

    def __init__(self, memory: ActiveMemory) -> None:
        self.memory = memory
        self._schema = load_schema(SCHEMA)
        memory.check_loaded(self.check_stored)  # a stored document is input: checked before anything uses it

    def check_stored(self, doc: etree._Element) -> None:
        """A document read back from the store: this base's tag, valid against the schema."""
        if doc.tag != self.tag:
            raise MemoryQueryError(f"the {self.kind} base holds <{self.tag}>, not <{doc.tag}>", source=f"<knowledge {self.kind}>")
        self.check(doc)

    def canonical(self, doc: etree._Element, attachments: Mapping[str, Attachment], now: float) -> tuple[etree._Element, dict[str, Attachment]]:
        raise NotImplementedError

    def check(self, doc: etree._Element) -> None:
        self._schema.check(doc, source=f"<knowledge {self.kind}>")
        if ("x" in doc.attrib) != ("y" in doc.attrib):  # a position is both or neither (XSD 1.0 cannot say so)
            raise MemoryQueryError(f"<{doc.tag}> has {'x' if 'x' in doc.attrib else 'y'} without "
                                   f"{'y' if 'x' in doc.attrib else 'x'}: a position is x and y, or none",
                                   source=f"<knowledge {self.kind}>")

    def same_as(self, doc: etree._Element) -> int | None:
        """The id of the stored document this one is a new version of, if any."""
        raise NotImplementedError

    def merged(self, old: etree._Element, new: etree._Element) -> etree._Element:
        """The new version of a stored document taught again (default: the new one as it is)."""
        return new

    def store(self, doc: etree._Element, attachments: Mapping[str, Attachment] | None = None, *, now: float = 0.0) -> tuple[int, bool]:
        """Store (or update the earlier version of) a document; return (id, was_update)."""
        canon, att = self.canonical(doc, attachments or {}, now)
        self.check(canon)
        old = self.same_as(canon)
        if old is None:
            return self.memory.insert(canon, att), False
        canon = self.merged(self.memory.get(old).xml, canon)
        self.check(canon)
        self.memory.update(old, canon, att if att else None)
        return old, True


class ObjectBase(KnowledgeBase):
    """Objects: type, name, owner, use, colour, position, size, visual features (attachments)."""

    kind = "objects"
    tag = "OBJECT"

    def __init__(self, *, store: SqliteStore | None = None) -> None:
        super().__init__(ActiveMemory("objects", store=store, indexes=OBJECT_INDEXES))

    def canonical(self, doc: etree._Element, attachments: Mapping[str, Attachment], now: float) -> tuple[etree._Element, dict[str, Attachment]]:
        if doc.tag != "OBJECT":
            raise MemoryQueryError(f"the object base stores <OBJECT>, not <{doc.tag}>", source="<knowledge objects>")
        d = describe(doc)
        if not d["type"]:
            raise MemoryQueryError("an object needs a type", source="<knowledge objects>", element="OBJECT")
        if doc.get("frame", "map") != "map":
            raise MemoryQueryError(f"object positions are stored in the map frame, not {doc.get('frame')!r}", source="<knowledge objects>")
        out = etree.Element("OBJECT", type=d["type"], name=d["name"] or d["type"])
        for key in ("owner", "use", "colour"):
            if d[key]:
                out.set(key, d[key])
        if doc.get("x") is not None or doc.get("y") is not None:  # none: taught from speech alone
            out.set("x", _fmt(_number(doc, "x", "an object")))
            out.set("y", _fmt(_number(doc, "y", "an object")))
        if doc.get("z") is not None:
            out.set("z", _fmt(_number(doc, "z", "an object")))
        if doc.get("size") is not None:
            out.set("size", _fmt(_number(doc, "size", "an object")))
        out.set("frame", "map")
        out.set("taught", _fmt(float(doc.get("taught", now))))
        for name in dict.fromkeys(_clean(a.get("name")) for a in doc.iterchildren("ATTRIBUTE")):
            if name:
                etree.SubElement(out, "ATTRIBUTE", name=name)  # "favourite"
        said = said_position(doc)
        if said is not None:
            etree.SubElement(out, "POSITION", relation=said[0], landmark=said[1])
        att = dict(attachments)
        for a in doc.iterchildren("attachment"):  # features sent inline (ES orders carry no binaries)
            if a.get("encoding") == "base64":
                att[a.get("name") or "features"] = decode_inline(a)
        return out, att

    def same_as(self, doc: etree._Element) -> int | None:
        """The stored object this teaching is about: the one of this type, name and owner when these
        single it out ("my cup" shown again elsewhere: it moved), else the one of this type and name
        within :data:`SAME_OBJECT` metres whose owner does not contradict (the same cup taught again
        where it stands; with or without the "my" that one of the two teachings missed: then within
        :data:`SAME_SPOT`, so a cup beside hers is not taken for hers). In both
        cases a stored object of another colour is never the one (her blue cup is not her red cup
        moved; a blue cup beside a red one is another cup)."""
        t, n, o, c = doc.get("type"), doc.get("name"), doc.get("owner", ""), doc.get("colour", "")
        # a cup does not change colour: one of another colour is another cup, wherever it stands
        ids = [i for i in self.memory.query_ids(where={"type": t, "name": n})
               if not (c and self.memory.get(i).xml.get("colour", "") not in ("", c))]
        owned = [i for i in ids if self.memory.get(i).xml.get("owner", "") == o]
        if owned and (o or n != t):
            return owned[-1]
        if doc.get("x") is None:  # taught from speech alone: what was said is all there is to go by
            return owned[-1] if owned else None
        x, y = float(doc.get("x")), float(doc.get("y"))  # type: ignore[arg-type]
        for i in reversed(ids):
            r = self.memory.get(i).xml
            if r.get("x") is None:
                continue
            ro = r.get("owner", "")
            if ro and o and ro != o:
                continue  # Tom's cup beside hers: another cup
            gate = SAME_OBJECT if ro == o else SAME_SPOT  # the owner said in only one of the two
            if math.hypot(float(r.get("x")) - x, float(r.get("y")) - y) <= gate:  # type: ignore[arg-type]
                return i
        return None

    def merged(self, old: etree._Element, new: etree._Element) -> etree._Element:
        """What was taught before and is not said again stays: the owner, use and colour, every
        attribute ("favourite" + "old" -> both) and, when the object still stands where it stood
        (within :data:`SAME_OBJECT`), the said position; the new teaching's position, time and
        features win. An object that moved ("my cup" shown again elsewhere) is no longer "at the
        window" because it was there when first taught."""
        out = deepcopy(new)
        for key in ("owner", "use", "colour"):
            if not out.get(key) and old.get(key):
                out.set(key, old.get(key))
        have = {a.get("name") for a in out.iterchildren("ATTRIBUTE")}
        extra = [a.get("name") for a in old.iterchildren("ATTRIBUTE") if a.get("name") not in have]
        pos = out.find("POSITION")
        for name in extra:
            a = etree.Element("ATTRIBUTE", name=name)  # ATTRIBUTEs come before the POSITION
            (pos.addprevious(a) if pos is not None else out.append(a))
        moved = old.get("x") is not None and new.get("x") is not None and math.hypot(
            float(old.get("x", "0")) - float(new.get("x", "0")), float(old.get("y", "0")) - float(new.get("y", "0"))) > SAME_OBJECT
        if pos is None and old.find("POSITION") is not None and not moved:
            out.append(deepcopy(old.find("POSITION")))
        return out

    def find(self, query: etree._Element) -> list[Record]:
        """Stored objects that fit a query frame (``<OBJECT type><OWNER name/></OBJECT>``), best first.

        A stored object fits when its type or name is the one asked for and
        nothing given in the question contradicts it (owner, colour, name);
        more agreeing details rank higher, then the most recently taught. A name
        that differs where the types agree is another word for the same kind of
        thing ("where is my telephone", stored as "phone": gen12), no contradiction;
        an object stored under the very word asked for still ranks first.
        """
        q = describe(query)
        ids: dict[int, None] = {}
        if q["type"]:
            ids.update(dict.fromkeys(self.memory.query_ids(where={"type": q["type"]})))
        if q["name"]:
            ids.update(dict.fromkeys(self.memory.query_ids(where={"name": q["name"]})))
            ids.update(dict.fromkeys(self.memory.query_ids(where={"type": q["name"]})))
        scored = []
        for i in sorted(ids):
            rec = self.memory.get(i)
            s = describe(rec.xml)
            score, ok = 0, True
            for key in ("owner", "colour", "name"):
                if q[key] and s[key]:
                    if q[key] == s[key] or (key == "name" and q[key] == s["type"]):
                        score += 1
                    elif key == "name" and q["type"] and q["type"] == s["type"]:
                        pass  # another word for the same type ("my telephone", stored "phone"): no point, no veto
                    else:
                        ok = False
            if q["type"] and s["type"] == q["type"]:
                score += 1
            if ok:
                scored.append((score, float(rec.xml.get("taught", "0")), i, rec))
        scored.sort(key=lambda t: (t[0], t[1], t[2]), reverse=True)
        return [t[3] for t in scored]


class PlaceBase(KnowledgeBase):
    """Places: a name and the robot's pose (map frame) when it was told."""

    kind = "places"
    tag = "PLACE"

    def __init__(self, *, store: SqliteStore | None = None) -> None:
        super().__init__(ActiveMemory("places", store=store, indexes=PLACE_INDEXES))

    def canonical(self, doc: etree._Element, attachments: Mapping[str, Attachment], now: float) -> tuple[etree._Element, dict[str, Attachment]]:
        if doc.tag != "PLACE":
            raise MemoryQueryError(f"the place base stores <PLACE>, not <{doc.tag}>", source="<knowledge places>")
        name = _clean(doc.get("name")) or _child_name(doc, "TITLE")
        if not name:
            raise MemoryQueryError("a place needs a name (name= or <TITLE name>)", source="<knowledge places>", element="PLACE")
        pose = doc.find("POSE") if doc.get("x") is None else doc
        if pose is None:
            raise MemoryQueryError(f"place {name!r} has no pose: the robot did not know where it was", source="<knowledge places>", element="PLACE")
        if pose.get("frame", "map") != "map":
            raise MemoryQueryError(f"place poses are stored in the map frame, not {pose.get('frame')!r}", source="<knowledge places>")
        out = etree.Element("PLACE", name=name, x=_fmt(_number(pose, "x", "a place pose")), y=_fmt(_number(pose, "y", "a place pose")),
                            theta=f"{_number(pose, 'theta', 'a place pose'):.5f}", frame="map")
        out.set("taught", _fmt(float(doc.get("taught", now))))
        return out, dict(attachments)

    def same_as(self, doc: etree._Element) -> int | None:
        ids = self.memory.query_ids(where={"name": doc.get("name", "")})
        return ids[-1] if ids else None

    def store(self, doc: etree._Element, attachments: Mapping[str, Attachment] | None = None, *, now: float = 0.0) -> tuple[int, bool]:
        """Store a place; ``replaces="kitchen"`` (the user corrected the name she had just given:
        "no, this is the bedroom") renames the place taught under the old name within
        :data:`SAME_PLACE` metres instead of keeping both."""
        wrong = _clean(doc.get("replaces"))
        if wrong:
            canon, _ = self.canonical(doc, attachments or {}, now)
            x, y = float(canon.get("x", "0")), float(canon.get("y", "0"))
            for rid in self.memory.query_ids(where={"name": wrong}):
                old = self.memory.get(rid).xml
                if math.hypot(float(old.get("x", "0")) - x, float(old.get("y", "0")) - y) <= SAME_PLACE:
                    if self.same_as(canon) is None:
                        self.check(canon)
                        self.memory.update(rid, canon, None)
                        return rid, True
                    self.memory.remove(rid)  # the right name is stored already: the wrong one goes
                    break
        return super().store(doc, attachments, now=now)

    def taught(self) -> list[TaughtPlace]:
        """Every place, in the order it was first taught."""
        out = []
        for rec in self.memory.query():
            x = rec.xml
            out.append(TaughtPlace(x.get("name", ""), float(x.get("x", "0")), float(x.get("y", "0")), float(x.get("theta", "0"))))
        return out
