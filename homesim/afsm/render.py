"""Looking at an AFSM: Graphviz DOT, Mermaid, and an object that displays itself in a notebook.

Pure functions of the model (py_trees' ``display``): nothing here changes
the machine or imports the engine. Categories become clusters (DOT) or
composite states (Mermaid); the initial state gets an arrow from a start
dot; transitions are labelled ``event [guard] / sends``; the current state
(if given) is highlighted.
"""

from __future__ import annotations

import shutil
import subprocess

from .model import Machine, Transition

_SEND_MARK = {"order": "↓", "condition": "↑"}


def _label(t: Transition, *, sends: bool = True) -> str:
    text = t.event
    if t.cond:
        text += f" [{t.cond}]"
    if sends and t.sends:
        text += " / " + ", ".join(f"{_SEND_MARK.get(s.kind, '')}{s.target}.{s.name}" for s in t.sends)
    return text


def _dot_str(s: str) -> str:
    return '"' + s.replace("\\", "\\\\").replace('"', '\\"') + '"'


def to_dot(m: Machine, *, current: str | None = None, sends: bool = True) -> str:
    """The machine as a Graphviz digraph (categories as ``cluster_`` subgraphs).

    Edges from or to a category use ``lhead``/``ltail`` on a representative
    leaf, so they are drawn to the cluster's border (``compound=true``).
    """
    lines = [f"digraph {_dot_str(m.name)} {{", "  compound=true;", "  rankdir=LR;",
             '  node [shape=box, style="rounded,filled", fillcolor=white, fontname="Helvetica"];',
             '  edge [fontname="Helvetica", fontsize=10];',
             '  __start [shape=point, width=0.15, label=""];']

    def rep(sid: str) -> str:
        return m.resolve_leaf(sid)

    def emit(sid: str, indent: str) -> None:
        st = m.states[sid]
        if st.children:
            lines.append(f"{indent}subgraph {_dot_str('cluster_' + sid)} {{")
            lines.append(f"{indent}  label={_dot_str(sid)}; style=rounded; color=gray40;")
            for c in st.children:
                emit(c, indent + "  ")
            lines.append(f"{indent}}}")
        else:
            fill = ', fillcolor="#ffe08a", penwidth=2' if sid == current else ""
            lines.append(f"{indent}{_dot_str(sid)} [label={_dot_str(sid)}{fill}];")

    for r in m.roots:
        emit(r, "  ")
    lines.append(f"  __start -> {_dot_str(m.initial_leaf())};")
    for owner, t in m.transitions():
        src = rep(owner)
        dst = rep(t.target) if t.target is not None else src
        attrs = [f"label={_dot_str(_label(t, sends=sends))}"]
        if m.states[owner].children:
            attrs.append(f"ltail={_dot_str('cluster_' + owner)}")
        if t.target is not None and m.states[t.target].children:
            attrs.append(f"lhead={_dot_str('cluster_' + t.target)}")
        if t.target is None:
            attrs.append("style=dashed")
        lines.append(f"  {_dot_str(src)} -> {_dot_str(dst)} [{', '.join(attrs)}];")
    lines.append("}")
    return "\n".join(lines) + "\n"


def _mm(text: str) -> str:
    """Mermaid transition labels cannot hold ':' or ';' or quotes; keep them readable."""
    return text.replace(":", "꞉").replace(";", ",").replace('"', "'").replace("#", "＃")


def _path(m: Machine, sid: str) -> list[str]:
    """Ancestors of ``sid`` from the outermost down to ``sid`` itself."""
    return list(reversed(m.ancestors(sid)))


def to_mermaid(m: Machine, *, current: str | None = None, sends: bool = True) -> str:
    """The machine as a Mermaid ``stateDiagram-v2`` (categories as composite states).

    Mermaid cannot draw an edge between states inside two different
    composite states, so such a transition is drawn between their outermost
    differing containers (inside the innermost common one) and its label
    names the real endpoints, e.g. ``PotentialPartner→Interacting: greeting``.
    """
    edges: dict[str | None, list[str]] = {}
    for owner, t in m.transitions():
        dst = t.target if t.target is not None else owner
        a, b = _path(m, owner), _path(m, dst)
        k = 0
        while k < min(len(a), len(b)) and a[k] == b[k]:
            k += 1
        if k == len(a) or k == len(b):
            # A self-loop, or a category and a state inside it: a loop on the outer one.
            outer = a if k == len(a) else b
            frm = to = outer[-1]
            lca = outer[-2] if len(outer) > 1 else None
        else:
            lca = a[k - 1] if k else None
            frm, to = a[k], b[k]
        prefix = f"{owner}→{dst}꞉ " if (frm, to) != (owner, dst) else ""
        edges.setdefault(lca, []).append(f"{frm} --> {to} : {_mm(prefix + _label(t, sends=sends))}")

    lines = ["stateDiagram-v2"]

    def emit(sid: str, indent: str) -> None:
        st = m.states[sid]
        if st.children:
            lines.append(f"{indent}state {sid} {{")
            init = _path(m, st.initial or st.children[0])[len(_path(m, sid))]
            lines.append(f"{indent}  [*] --> {init}")
            for c in st.children:
                emit(c, indent + "  ")
            lines.extend(indent + "  " + e for e in edges.get(sid, []))
            lines.append(f"{indent}}}")
        else:
            lines.append(f"{indent}{sid}")

    for r in m.roots:
        emit(r, "  ")
    lines.append(f"  [*] --> {_path(m, m.initial if m.initial is not None else m.roots[0])[0]}")
    lines.extend("  " + e for e in edges.get(None, []))
    if current is not None:
        lines.append("  classDef current fill:#ffe08a,stroke:#b58900,stroke-width:2px")
        lines.append(f"  class {current} current")
    return "\n".join(lines) + "\n"


class AFSMView:
    """A machine that shows itself in Jupyter: Mermaid in Markdown, SVG when Graphviz is installed.

    ``AFSMView(machine, current="Following")`` highlights a state, e.g. the
    supervisor's current one while stepping through a run.
    """

    def __init__(self, machine: Machine, *, current: str | None = None, sends: bool = True) -> None:
        self.machine = machine
        self.current = current
        self.sends = sends

    def dot(self) -> str:
        return to_dot(self.machine, current=self.current, sends=self.sends)

    def mermaid(self) -> str:
        return to_mermaid(self.machine, current=self.current, sends=self.sends)

    def _repr_markdown_(self) -> str:
        return "```mermaid\n" + self.mermaid() + "```\n"

    def _repr_svg_(self) -> str | None:
        """SVG via the ``dot`` program if it is installed (None tells Jupyter to use another form)."""
        exe = shutil.which("dot")
        if exe is None:
            return None
        done = subprocess.run([exe, "-Tsvg"], input=self.dot().encode("utf-8"), capture_output=True, check=False)
        return done.stdout.decode("utf-8") if done.returncode == 0 else None

    def __repr__(self) -> str:
        m = self.machine
        return (f"AFSMView({m.name!r}: {len(m.leaves())} states, {len(m.categories())} categories, "
                f"{sum(1 for _ in m.transitions())} transitions, current={self.current!r})")
