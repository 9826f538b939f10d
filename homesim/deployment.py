"""Deployments as documents: hosts, links and which module runs where.

A deployment document (``<deployment name default-host>``, schema
``homesim/schemas/deployment.xsd``) lists link kinds (:class:`~homesim.network.LinkModel`
in ms and Mbit/s), hosts (the link each is attached by, optionally another
link for what it sends, its CPU speed), routes (the link one ordered pair of
hosts talks over, overriding their attachments) and placements (a module,
i.e. a bus participant by name, on a host). A run loads
one (the simulated system's default), lets the scenario override parts of it
(:class:`Override`: links, hosts and placements replaced by name) and applies
it to the simulation's :class:`~homesim.network.Network` before any module
joins the bus.

The kernel knows no particular system: the document names hosts and modules
as data. How it fails: every problem is an :class:`~homesim.errors.InputError`
naming the file, the line and the element (a schema violation, a name given
twice, a host or route on an unknown link, a route or placement on an unknown
host, a route from a host to itself, and, when the caller says which modules
exist, a placement of a module that does not); nothing is
applied from a document that does not load.

Which modules exist is the simulated system's to say, never the kernel's: the
loading functions take ``modules`` (the names a placement may use; None: not
checked), and the simulated system passes its own list (through the run package,
its scenario check and its ``homesim check`` document type, an entry point).
"""

from __future__ import annotations

import os
from collections.abc import Collection
from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import Any

from lxml import etree

from .errors import HomesimError, InputError
from .network import LinkModel, Network
from .suggest import did_you_mean
from .xmlio import load_schema, parse_file

SCHEMA = Path(__file__).with_name("schemas") / "deployment.xsd"


class DeploymentError(InputError):
    """A deployment document (or a scenario's override) cannot be accepted."""


class DeploymentProblems(DeploymentError):
    """Several problems of one deployment (``homesim check`` lists them all); reads as the first."""

    def __init__(self, problems: list[DeploymentError]) -> None:
        if not problems:
            raise ValueError("DeploymentProblems needs at least one problem")
        self.problems = list(problems)
        first, more = problems[0], len(problems) - 1
        msg = first.message + (f" (and {more} more problem{'s' if more > 1 else ''}; 'homesim check' lists them)" if more else "")
        super().__init__(msg, source=first.source, line=first.line, element=first.element)


def _raise_all(found: list[DeploymentError]) -> None:
    """Raise the problems found (one: itself; more: :class:`DeploymentProblems`)."""
    if len(found) == 1:
        raise found[0]
    if found:
        raise DeploymentProblems(found)


@dataclass(frozen=True)
class HostSpec:
    """A computer: the link kind it is attached by, its CPU speed in MHz (None: unknown), the CPU's name.

    ``uplink``: the link kind its outgoing messages take, when not ``link``
    (an attachment slower one way, e.g. a WLAN whose access point queues
    the frames to this station).
    """

    name: str
    link: str
    cpu_mhz: float | None = None
    cpu: str = ""
    line: int | None = None
    uplink: str | None = None


@dataclass(frozen=True)
class RouteSpec:
    """Messages from host ``src`` to host ``dst`` take ``link`` (one direction; overrides both hosts' links)."""

    src: str
    dst: str
    link: str
    line: int | None = None

    @property
    def key(self) -> tuple[str, str]:
        return (self.src, self.dst)


@dataclass(frozen=True)
class Override:
    """What a scenario changes of a run's deployment (each part replaces by name).

    ``href``: a whole document that replaces the default first (resolved
    against the scenario's directory).
    """

    links: tuple[LinkModel, ...] = ()
    hosts: tuple[HostSpec, ...] = ()
    placement: tuple[tuple[str, str], ...] = ()
    default_host: str | None = None
    href: str | None = None
    source: str = "<override>"
    line: int | None = None
    routes: tuple[RouteSpec, ...] = ()
    #: module -> the line of its <place> (errors name it)
    place_lines: tuple[tuple[str, int | None], ...] = ()


@dataclass(frozen=True)
class Deployment:
    """A whole deployment: links, hosts, placements and the host of every module not placed."""

    name: str
    default_host: str
    links: tuple[LinkModel, ...]
    hosts: tuple[HostSpec, ...]
    placement: tuple[tuple[str, str], ...] = ()
    description: str = ""
    source: str = "<deployment>"
    overridden: bool = field(default=False, compare=False)
    routes: tuple[RouteSpec, ...] = ()

    def host_of(self, module: str) -> str:
        """The host ``module`` runs on."""
        return dict(self.placement).get(module, self.default_host)

    def host(self, name: str) -> HostSpec:
        """The host named ``name`` (KeyError if none)."""
        for h in self.hosts:
            if h.name == name:
                return h
        raise KeyError(name)

    def link(self, name: str) -> LinkModel:
        """The link kind named ``name`` (KeyError if none)."""
        for lk in self.links:
            if lk.name == name:
                return lk
        raise KeyError(name)

    def merged(self, override: Override, *, modules: Collection[str] | None = None) -> Deployment:
        """This deployment with ``override``'s links, hosts, routes (by host pair) and placements replacing those of the same name.

        ``modules``: the modules that exist (a placement of another is refused at its line); None: not checked.
        """
        links = {lk.name: lk for lk in self.links}
        links.update((lk.name, lk) for lk in override.links)
        hosts = {h.name: h for h in self.hosts}
        hosts.update((h.name, h) for h in override.hosts)
        placement = dict(self.placement)
        placement.update(override.placement)
        routes = {r.key: r for r in self.routes}
        routes.update((r.key, r) for r in override.routes)
        out = replace(self, links=tuple(links.values()), hosts=tuple(hosts.values()),
                      placement=tuple(sorted(placement.items())), routes=tuple(routes.values()),
                      default_host=override.default_host or self.default_host, overridden=True)
        found = _check_refs(out, override.source, override.line, dict(override.place_lines))
        found += _check_modules(override.placement, modules, override.source, override.line, dict(override.place_lines))
        _raise_all(sorted(found, key=lambda e: e.line or 0))
        return out

    def apply(self, network: Network) -> None:
        """Declare the links, hosts and routes on ``network`` and place every module named."""
        for lk in self.links:
            network.set_link(lk)
        for h in self.hosts:
            network.add_host(h.name, link=h.link, uplink=h.uplink, speed_mhz=h.cpu_mhz)
        for r in self.routes:
            network.set_route(r.src, r.dst, r.link)
        for module, host in self.placement:
            network.place(module, host)
        network.default_host = self.default_host

    def as_dict(self) -> dict[str, Any]:
        """Plain data for a run summary: the name, hosts (link, uplink, CPU), routes and placements."""
        out: dict[str, Any] = {
            "name": self.name,
            "overridden": self.overridden,
            "hosts": {h.name: {"link": h.link, **({"uplink": h.uplink} if h.uplink else {}),
                               **({"cpu_mhz": h.cpu_mhz} if h.cpu_mhz else {}),
                               **({"cpu": h.cpu} if h.cpu else {})} for h in self.hosts},
            "default_host": self.default_host,
            "placement": dict(self.placement),
        }
        if self.routes:
            out["routes"] = {f"{r.src}->{r.dst}": r.link for r in sorted(self.routes, key=lambda r: r.key)}
        return out


# ------------------------------------------------------------------ loading
def _fail(msg: str, source: str, el: etree._Element | None = None, line: int | None = None) -> DeploymentError:
    tag = etree.QName(el).localname if el is not None and isinstance(el.tag, str) else None
    return DeploymentError(msg, source=source, line=el.sourceline if el is not None else line, element=tag)


def _float(el: etree._Element, name: str, default: float) -> float:
    v = el.get(name)
    return default if v is None else float(v)


def _link(el: etree._Element, source: str) -> LinkModel:
    ms = 1e-3
    try:
        return LinkModel(
            el.get("name", ""), _float(el, "min-ms", 0) * ms, _float(el, "max-ms", 0) * ms,
            jitter_s=_float(el, "jitter-ms", 0) * ms, loss=_float(el, "loss", 0),
            bandwidth_bps=_float(el, "bandwidth-mbit", 0) * 1e6, retransmit_s=_float(el, "retransmit-ms", 0) * ms,
            backoff=_float(el, "backoff", 2.0), max_retries=int(el.get("max-retries", "7")),
        )
    except HomesimError as exc:
        raise _fail(str(exc), source, el) from exc


def _host(el: etree._Element) -> HostSpec:
    mhz = el.get("cpu-mhz")
    return HostSpec(el.get("name", ""), el.get("link", ""), None if mhz is None else float(mhz), el.get("cpu", ""),
                    el.sourceline, el.get("uplink"))


def _route(el: etree._Element, source: str) -> RouteSpec:
    src, dst = el.get("from", ""), el.get("to", "")
    if src == dst:
        raise _fail(f"route from {src!r} to itself: a host talks to itself over the local link", source, el)
    return RouteSpec(src, dst, el.get("link", ""), el.sourceline)


_KEYS = {"link": ("name",), "host": ("name",), "place": ("module",), "route": ("from", "to")}


def _children(parent: etree._Element, source: str, place_lines: dict[str, int | None] | None = None,
              found: list[DeploymentError] | None = None
              ) -> tuple[list[LinkModel], list[HostSpec], list[tuple[str, str]], list[RouteSpec]]:
    """Links, hosts, placements and routes of ``parent``, each name (a route: each pair) at most once
    (else an error at the repeat). ``found``: collect the problems there (the bad element is left
    out) instead of raising the first."""
    links: list[LinkModel] = []
    hosts: list[HostSpec] = []
    placement: list[tuple[str, str]] = []
    routes: list[RouteSpec] = []
    seen: dict[tuple[str, str], int | None] = {}
    for el in parent:
        if not isinstance(el.tag, str):
            continue
        tag = etree.QName(el).localname
        key_attrs = _KEYS.get(tag)
        if key_attrs is None:
            continue
        key = (tag, " -> ".join(el.get(a, "") for a in key_attrs))
        try:
            if key in seen:
                raise _fail(f"{tag} {key[1]!r} is given twice (first at line {seen[key]})", source, el)
            seen[key] = el.sourceline
            if tag == "link":
                links.append(_link(el, source))
            elif tag == "route":
                routes.append(_route(el, source))
        except DeploymentError as exc:
            if found is None:
                raise
            found.append(exc)
            continue
        if tag == "host":
            hosts.append(_host(el))
        elif tag == "place":
            placement.append((el.get("module", ""), el.get("host", "")))
            if place_lines is not None:
                place_lines[el.get("module", "")] = el.sourceline
    return links, hosts, placement, routes


def _check_refs(d: Deployment, source: str, line: int | None = None,
                place_lines: dict[str, int | None] | None = None) -> list[DeploymentError]:
    """Every reference of ``d`` (a host's link and uplink, a route's hosts and link, a placement's
    host, the default host) names something declared: the problems, in the document's order."""
    found: list[DeploymentError] = []
    links = {lk.name for lk in d.links} | {"local"}
    hosts = {h.name for h in d.hosts}
    for h in d.hosts:
        if h.link not in links:
            found.append(DeploymentError(f"host {h.name!r} is attached by unknown link {h.link!r}; links: {sorted(links)}",
                                         source=source, line=h.line or line, element="host"))
        if h.uplink is not None and h.uplink not in links:
            found.append(DeploymentError(f"host {h.name!r} sends over unknown link {h.uplink!r} (uplink); links: "
                                         f"{sorted(links)}", source=source, line=h.line or line, element="host"))
    for r in d.routes:
        for end, host in (("from", r.src), ("to", r.dst)):
            if host not in hosts:
                found.append(DeploymentError(f"route {r.src!r} -> {r.dst!r}: {end} unknown host {host!r}; hosts: "
                                             f"{sorted(hosts)}", source=source, line=r.line or line, element="route"))
        if r.link not in links:
            found.append(DeploymentError(f"route {r.src!r} -> {r.dst!r} takes unknown link {r.link!r}; links: "
                                         f"{sorted(links)}", source=source, line=r.line or line, element="route"))
    for module, host in d.placement:
        if host not in hosts:
            found.append(DeploymentError(f"module {module!r} is placed on unknown host {host!r}; hosts: {sorted(hosts)}",
                                         source=source, line=(place_lines or {}).get(module) or line, element="place"))
    if d.default_host not in hosts:
        found.append(DeploymentError(f"default-host {d.default_host!r} is not a host; hosts: {sorted(hosts)}",
                                         source=source, line=line, element="deployment"))
    return found


def _check_modules(placement: Collection[tuple[str, str]], modules: Collection[str] | None, source: str,
                   line: int | None = None, place_lines: dict[str, int | None] | None = None) -> list[DeploymentError]:
    """Every placed module is one of ``modules`` (None: any name; the system says which exist)."""
    if modules is None:
        return []
    found: list[DeploymentError] = []
    known = sorted(set(modules))
    for module, _host in placement:  # in the document's order
        if module not in known:
            found.append(DeploymentError(f"no module {module!r} to place{did_you_mean(module, known)}; modules: "
                                         f"{', '.join(known) or '(none)'}",
                                         source=source, line=(place_lines or {}).get(module) or line, element="place"))
    return found


def _validate(el: etree._Element, source: str) -> None:
    schema = load_schema(SCHEMA)
    problems = schema.errors(el)
    _raise_all([DeploymentError(f"does not satisfy deployment.xsd: {msg}", source=source, line=line or el.sourceline)
                for line, msg in problems])


def from_element(root: etree._Element, *, source: str = "<deployment>", modules: Collection[str] | None = None) -> Deployment:
    """A :class:`Deployment` from a parsed ``<deployment>`` element (schema, then names and references;
    each placed module one of ``modules`` unless that is None)."""
    if root.tag != "deployment":
        raise _fail(f"root element is <{root.tag}>, not <deployment>", source, root)
    _validate(root, source)
    lines: dict[str, int | None] = {}
    found: list[DeploymentError] = []
    links, hosts, placement, routes = _children(root, source, lines, found)
    desc = root.find("description")
    d = Deployment(root.get("name", ""), root.get("default-host", ""), tuple(links), tuple(hosts),
                   tuple(sorted(placement)), " ".join((desc.text or "").split()) if desc is not None else "", source,
                   routes=tuple(routes))
    found += _check_refs(d, source, root.sourceline, lines)
    # Every placement's host must be a host; every module at most once (checked in _children).
    found += _check_modules(placement, modules, source, root.sourceline, lines)
    _raise_all(sorted(found, key=lambda e: e.line or 0))
    return d


def load(path: str | os.PathLike[str], *, modules: Collection[str] | None = None) -> Deployment:
    """Load and check a deployment document (the hardened parser, the schema, the references, the
    placed modules against ``modules`` unless that is None)."""
    source = str(path)
    return from_element(parse_file(path), source=source, modules=modules)


def override_from_element(el: etree._Element, *, source: str) -> Override:
    """A scenario's ``<deployment [href] [default-host]>`` with link/host/route/place children, checked.

    Each child must satisfy the deployment schema; references (a host's link,
    a placement's host) are checked when the override is merged into the
    run's deployment, where the rest of the names are known.
    """
    schema = load_schema(SCHEMA)
    for child in el:
        if not isinstance(child.tag, str):
            continue
        if child.tag not in ("link", "host", "route", "place"):
            raise _fail(f"<{child.tag}> is not part of a deployment (link, host, route, place)", source, child)
        problems = schema.errors(child)
        if problems:
            raise DeploymentError(f"does not satisfy deployment.xsd: {problems[0][1]}", source=source,
                                  line=child.sourceline, element=child.tag)
    lines: dict[str, int | None] = {}
    links, hosts, placement, routes = _children(el, source, lines)
    href = el.get("href")
    if href is not None and not href.strip():
        raise _fail("href is empty", source, el)
    return Override(tuple(links), tuple(hosts), tuple(placement), el.get("default-host"), href, source, el.sourceline,
                    tuple(routes), tuple(sorted(lines.items())))


def resolve(default: Deployment | str | os.PathLike[str], override: Override | None, *,
            base_dir: str | os.PathLike[str] | None = None, modules: Collection[str] | None = None) -> Deployment:
    """The deployment a run uses: ``default`` (or the override's ``href`` document), then the override's parts.

    ``modules``: the modules that exist; every placement (the default's, the ``href`` document's, the
    override's) must name one of them, else a :class:`DeploymentError` at its line. None: not checked.
    """
    if isinstance(default, Deployment):
        base = default
        _raise_all(_check_modules(base.placement, modules, base.source))
    else:
        base = load(default, modules=modules)
    if override is None:
        return base
    if override.href is not None:
        path = Path(override.href)
        if not path.is_absolute() and base_dir is not None:
            path = Path(base_dir) / path
        try:
            base = load(path, modules=modules)
        except DeploymentError:
            raise
        except InputError as exc:
            raise DeploymentError(f"deployment href={override.href!r}: {exc.message}", source=override.source,
                                  line=override.line, element="deployment") from exc
    return base.merged(override, modules=modules)


def check_file(path: str, *, modules: Collection[str] | None = None) -> list[InputError]:
    """``homesim check``: every problem of a deployment document (empty when it loads; placed modules
    checked against ``modules`` unless that is None)."""
    try:
        load(path, modules=modules)
    except DeploymentProblems as exc:
        return list(exc.problems)
    except InputError as exc:
        return [exc]
    return []


__all__ = ("Deployment", "DeploymentError", "DeploymentProblems", "HostSpec", "Override", "RouteSpec", "check_file", "from_element", "load",
           "override_from_element", "resolve")
