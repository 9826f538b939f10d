"""libxml2's XML Schema messages in the documented form: ``<element>`` and what is wrong, saying what is expected.

libxml2 words a problem as ``Element 'room', attribute 'nme': The attribute
'nme' is not allowed.`` or ``... 'abc' is not a valid value of the atomic
type 'coord'.``, and a refused pattern as the whole regular expression. A
scenario author needs the element (the error's ``<element>`` field), the
attribute and value, and what would be accepted: a number in a range, one of
a set, a form in words (:class:`Wording`, read from the schema itself), and
the closest allowed name when one is close (a misspelt element or attribute).

How it fails: a message of a form not known here is kept in libxml2's words.
"""

from __future__ import annotations

import re
from collections.abc import Iterable, Mapping
from dataclasses import dataclass, field

from lxml import etree

from ..suggest import closest

XS = "{http://www.w3.org/2001/XMLSchema}"

_MESSAGE = re.compile(r"^Element '(?P<element>[^']*)'(?:, attribute '(?P<attribute>[^']*)')?: (?P<rest>.*?)\.?$", re.S)
_PATTERN = re.compile(r"^\[facet 'pattern'\] The value '(?P<value>.*)' is not accepted by the pattern '(?P<pattern>.*)'$", re.S)
_ENUM = re.compile(r"^\[facet 'enumeration'\] The value '(?P<value>.*)' is not an element of the set \{(?P<set>.*)\}$", re.S)
_MIN = re.compile(r"^\[facet '(?:minInclusive|minExclusive)'\] The value '(?P<value>.*)' (?:is less than the minimum value allowed "
                  r"\('(?P<low>[^']*)'\)|must be greater than '(?P<above>[^']*)')$", re.S)
_MAX = re.compile(r"^\[facet '(?:maxInclusive|maxExclusive)'\] The value '(?P<value>.*)' (?:is greater than the maximum value allowed "
                  r"\('(?P<high>[^']*)'\)|must be less than '(?P<below>[^']*)')$", re.S)
_ATOMIC = re.compile(r"^'(?P<value>.*)' is not a valid value of the (?:local )?(?:atomic|union|list) type(?: '(?P<type>[^']*)')?$", re.S)
_NOT_ALLOWED = re.compile(r"^The attribute '(?P<attribute>[^']*)' is not allowed$")
_REQUIRED = re.compile(r"^The attribute '(?P<attribute>[^']*)' is required but missing$")
_UNEXPECTED = re.compile(r"^This element is not expected(?:\. Expected is (?:one of )?\( (?P<expected>.*) \))?$", re.S)
_MISSING = re.compile(r"^Missing child element\(s\)\. Expected is (?:one of )?\( (?P<expected>.*) \)$", re.S)
_TEXT = re.compile(r"^Character content other than whitespace is not allowed")

#: Built-in XSD types in words.
BUILTIN = {
    "xs:double": "a number such as 1.5 or -2e3", "xs:float": "a number such as 1.5 or -2e3", "xs:decimal": "a decimal number",
    "xs:boolean": "true or false", "xs:integer": "a whole number", "xs:int": "a whole number",
    "xs:nonNegativeInteger": "a whole number 0 or more", "xs:positiveInteger": "a whole number 1 or more",
    "xs:NCName": "a name without spaces or colons (a letter or '_', then letters, digits, '_', '-', '.')",
    "xs:token": "text", "xs:string": "text",
}


@dataclass(frozen=True)
class Wording:
    """What a schema's own simple types accept, in words: by pattern and by type name."""

    patterns: Mapping[str, str] = field(default_factory=dict)
    types: Mapping[str, str] = field(default_factory=dict)
    attributes: Mapping[str, frozenset[str]] = field(default_factory=dict)  # element name -> the attributes it may have
    children: Mapping[str, tuple[str, ...]] = field(default_factory=dict)  # element name -> the child elements it may hold
    local: Mapping[tuple[str, str], str] = field(default_factory=dict)  # (element, attribute) -> its anonymous type in words

    def of_type(self, name: str | None) -> str:
        if not name:
            return "a value this attribute accepts"
        return self.types.get(name) or BUILTIN.get(name) or f"a value of type {name!r}"


def restriction_words(rest: etree._Element, patterns: Mapping[str, str] | None = None) -> str:
    """One ``xs:restriction`` in words: 'a number such as 1.5 ..., at least 0 and at most 9', 'one of 'a', 'b''."""
    base = BUILTIN.get(rest.get("base", ""), "a value")
    facets = {f.tag.removeprefix(XS): f.get("value") for f in rest}
    if "enumeration" in facets:
        return "one of " + ", ".join(repr(f.get("value")) for f in rest.iter(XS + "enumeration"))
    bounds = []
    for facet, words in (("minInclusive", "at least"), ("minExclusive", "greater than"), ("maxInclusive", "at most"),
                         ("maxExclusive", "less than")):
        if facet in facets:
            bounds.append(f"{words} {facets[facet]}")
    text = base + (f", {' and '.join(bounds)}" if bounds else "")
    pattern = facets.get("pattern")
    if pattern is not None and (digits := re.fullmatch(r"\[0-9\]\{1,(\d+)\}", pattern)) is not None:
        text += f" (at most {digits.group(1)} digits)"
    elif pattern is not None and patterns and pattern in patterns:
        text += f" ({patterns[pattern]})"
    if "minLength" in facets or "maxLength" in facets:
        text += f" ({facets.get('minLength', '0')} to {facets.get('maxLength', 'any number of')} characters)"
    return text


def type_words(schema: etree._Element) -> dict[str, str]:
    """The named simple types of ``schema`` that restrict a number, as 'a number from LOW to HIGH' (and so on)."""
    out: dict[str, str] = {}
    for st in schema.iter(XS + "simpleType"):
        name = st.get("name")
        rest = st.find(XS + "restriction")
        if name is None or rest is None:
            continue
        out[name] = restriction_words(rest)
    return out


def local_type_words(schema: etree._Element, patterns: Mapping[str, str] | None = None) -> dict[tuple[str, str], str]:
    """(element, attribute) -> the attribute's anonymous simple type in words (libxml2 names no type for these)."""
    users: dict[str, list[str]] = {}  # complex type name -> the elements declared with it
    for el in schema.iter(XS + "element"):
        if el.get("name") and el.get("type"):
            users.setdefault(el.get("type"), []).append(el.get("name"))
    out: dict[tuple[str, str], str] = {}
    for attr in schema.iter(XS + "attribute"):
        rest = attr.find(f"{XS}simpleType/{XS}restriction")
        if attr.get("name") is None or rest is None:
            continue
        owner = attr.getparent()
        while owner is not None and owner.tag not in (XS + "element", XS + "complexType", XS + "attributeGroup"):
            owner = owner.getparent()
        if owner is None:
            continue
        if owner.tag == XS + "complexType" and owner.get("name") is None:
            owner = owner.getparent()  # an element's inline type
        elements = [owner.get("name")] if owner.tag == XS + "element" else users.get(owner.get("name", ""), [])
        for element in elements:
            if element:
                out[(element, attr.get("name"))] = restriction_words(rest, patterns)
    return out


def element_attributes(schema: etree._Element) -> dict[str, frozenset[str]]:
    """Element name -> every attribute the schema allows it (over all the places the element is declared)."""
    groups = {g.get("name"): g for g in schema.iter(XS + "attributeGroup") if g.get("name")}
    complex_types = {t.get("name"): t for t in schema.iter(XS + "complexType") if t.get("name")}

    def names(node: etree._Element, depth: int = 0) -> set[str]:
        out = {a.get("name") for a in node.iter(XS + "attribute") if a.get("name")}
        for ref in node.iter(XS + "attributeGroup"):
            if ref.get("ref") in groups and depth < 8:
                out |= names(groups[ref.get("ref")], depth + 1)
        for ext in node.iter(XS + "extension"):
            if ext.get("base") in complex_types and depth < 8:
                out |= names(complex_types[ext.get("base")], depth + 1)
        return out

    found: dict[str, set[str]] = {}
    for el in schema.iter(XS + "element"):
        name = el.get("name")
        if name is None:
            continue
        body = complex_types.get(el.get("type")) if el.get("type") else el.find(XS + "complexType")
        if body is not None:  # its own attributes, not those of the elements declared inside its content
            for child in body:
                if child.tag not in (XS + "sequence", XS + "choice", XS + "all"):
                    found.setdefault(name, set()).update(names(child))
    return {k: frozenset(v) for k, v in found.items()}


def element_children(schema: etree._Element) -> dict[str, tuple[str, ...]]:
    """Element name -> the child elements its content model allows, in schema order (over all its declarations).

    libxml2 names what it expected only for some content models (not for an
    unbounded ``xs:choice``); this is what a refusal of a child then lists."""
    groups = {g.get("name"): g for g in schema.iter(XS + "group") if g.get("name")}
    complex_types = {t.get("name"): t for t in schema.iter(XS + "complexType") if t.get("name")}
    model = (XS + "sequence", XS + "choice", XS + "all")

    def kids(node: etree._Element, depth: int = 0) -> list[str]:
        out: list[str] = []
        for child in node:
            if child.tag == XS + "element" and (child.get("name") or child.get("ref")):
                out.append((child.get("name") or child.get("ref", "")).rsplit(":", 1)[-1])
            elif child.tag in model:
                out += kids(child, depth)
            elif child.tag == XS + "group" and child.get("ref") in groups and depth < 8:
                out += kids(groups[child.get("ref")], depth + 1)
            elif child.tag in (XS + "complexContent", XS + "extension") and depth < 8:
                if child.tag == XS + "extension" and child.get("base") in complex_types:
                    out += kids(complex_types[child.get("base")], depth + 1)
                out += kids(child, depth + 1)
        return out

    found: dict[str, list[str]] = {}
    for el in schema.iter(XS + "element"):
        name = el.get("name")
        body = complex_types.get(el.get("type")) if el.get("type") else el.find(XS + "complexType")
        if name is None or body is None:
            continue
        names = found.setdefault(name, [])
        names += [k for k in kids(body) if k not in names]
    return {k: tuple(v) for k, v in found.items() if v}


def describe(message: str, wording: Wording, *, missing: Iterable[str] = (), parent: str | None = None) -> tuple[str | None, str]:
    """(element, what is wrong and what is expected) for one libxml2 message.

    ``missing``: the attributes the same element lacks (a misspelt attribute is then both not
    allowed and missing: the closest missing one is suggested). ``parent``: the element's
    parent, whose allowed children are listed when libxml2 does not say what it expected."""
    m = _MESSAGE.match(message.strip())
    if m is None:
        return None, message
    element = m.group("element").rsplit("}", 1)[-1]
    attribute, rest = m.group("attribute"), m.group("rest")
    what = f"{attribute}=" if attribute else "the text"
    if (p := _PATTERN.match(rest)) is not None:
        form = wording.patterns.get(p.group("pattern"), "the form the schema requires")
        return element, f"{what}{p.group('value')!r} is not valid; expected {attribute or 'text'}: {form}"
    if (p := _ENUM.match(rest)) is not None:
        choices = re.findall(r"'([^']*)'", p.group("set"))
        near = closest(p.group("value"), choices)
        hint = f" (did you mean {near!r}?)" if near else ""
        return element, f"{what}{p.group('value')!r} is not valid; expected one of {', '.join(map(repr, choices))}{hint}"
    if (p := _MIN.match(rest)) is not None:
        low = f"at least {p.group('low')}" if p.group("low") is not None else f"greater than {p.group('above')}"
        return element, f"{what}{p.group('value')!r} is too small; expected {low}"
    if (p := _MAX.match(rest)) is not None:
        high = f"at most {p.group('high')}" if p.group("high") is not None else f"less than {p.group('below')}"
        return element, f"{what}{p.group('value')!r} is too large; expected {high}"
    if (p := _ATOMIC.match(rest)) is not None:
        words = wording.local.get((element, attribute or "")) if p.group("type") is None else None
        return element, f"{what}{p.group('value')!r} is not valid; expected {words or wording.of_type(p.group('type'))}"
    if (p := _NOT_ALLOWED.match(rest)) is not None:
        allowed = sorted(wording.attributes.get(element, ()))
        near = closest(p.group("attribute"), missing) or closest(p.group("attribute"), allowed)
        hint = f" (did you mean {near}=?)" if near else ""
        listed = f"; <{element}> takes {', '.join(a + '=' for a in allowed)}" if allowed else ""
        return element, f"attribute {p.group('attribute')}= is not allowed here{hint}{listed}"
    if (p := _REQUIRED.match(rest)) is not None:
        return element, f"attribute {p.group('attribute')}= is required but missing"
    if (p := _UNEXPECTED.match(rest)) is not None:
        expected = _names(p.group("expected")) or list(wording.children.get(parent or "", ()))
        if not expected:
            return element, "this element is not expected here"
        near = closest(element, expected)
        hint = f" (did you mean <{near}>?)" if near and near != element and len(expected) > 1 else ""
        return element, f"<{element}> is not expected here; expected {_one_of(expected)}{hint}"
    if (p := _MISSING.match(rest)) is not None:
        return element, f"a child element is missing; expected {_one_of(_names(p.group('expected')))}"
    if _TEXT.match(rest):
        return element, "text is not allowed here: this element holds child elements only"
    return element, rest


def describe_all(errors: Iterable[tuple[int, str]], wording: Wording,
                 parents: Mapping[tuple[int, str], str] | None = None) -> list[tuple[int, str | None, str]]:
    """(line, element, words) for every (line, libxml2 message) of one validation, in order.

    ``parents``: (line, element name) -> its parent's name, for the elements libxml2 did not expect."""
    errors = list(errors)
    missing: dict[int, list[str]] = {}
    for line, message in errors:
        m = _MESSAGE.match(message.strip())
        r = _REQUIRED.match(m.group("rest")) if m is not None else None
        if r is not None:
            missing.setdefault(line, []).append(r.group("attribute"))
    paired: set[tuple[int, str]] = set()  # (line, required attribute) a misspelt one on that line stands for
    for line, message in errors:
        m = _MESSAGE.match(message.strip())
        n = _NOT_ALLOWED.match(m.group("rest")) if m is not None else None
        if n is not None and (near := closest(n.group("attribute"), missing.get(line, ()))) is not None:
            paired.add((line, near))
    out = []
    for line, message in errors:
        m = _MESSAGE.match(message.strip())
        r = _REQUIRED.match(m.group("rest")) if m is not None else None
        if r is not None and (line, r.group("attribute")) in paired:
            continue  # said once: "attribute stat= is not allowed here (did you mean state=?)"
        parent = (parents or {}).get((line, m.group("element"))) if m is not None else None
        out.append((line, *describe(message, wording, missing=missing.get(line, ()), parent=parent)))
    return out


def _names(expected: str | None) -> list[str]:
    return [n.strip().rsplit("}", 1)[-1] for n in (expected or "").split(",") if n.strip()]


def _one_of(names: list[str]) -> str:
    tags = [f"<{n}>" for n in names]
    return tags[0] if len(tags) == 1 else "one of " + ", ".join(tags)
