"""The active memory against a plain dict model (Hypothesis stateful): insert, update, remove, free XPath
and indexed queries, subscriptions with their actions, and reloading from the SQLite store."""

from __future__ import annotations

import shutil
import tempfile
from pathlib import Path

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from hypothesis.stateful import Bundle, RuleBasedStateMachine, consumes, initialize, invariant, precondition, rule
from lxml import etree

from homesim.errors import MemoryQueryError
from homesim.memory import ActiveMemory, SqliteStore

from .conftest import examples

TYPES = ("cup", "plant", "book")
NAMES = ("a", "b", "c")
OWNERS = (None, "anna", "tom")

# XPath -> the same rule in Python over the model's (type, name, owner, child) tuple.
XPATHS = {
    "/OBJECT[@type='cup']": lambda d: d[0] == "cup",
    "/OBJECT[@owner]": lambda d: d[2] is not None,
    "/*[@name='a' or @name='b']": lambda d: d[1] in ("a", "b"),
    "count(/OBJECT/NOTE) > 0": lambda d: d[3],
    "/OBJECT[@type='plant' and not(@owner)]": lambda d: d[0] == "plant" and d[2] is None,
    "self::OBJECT[@owner='tom']/@name": lambda d: d[2] == "tom",
}
INDEXES = {"type": "@type", "owner": "@owner"}

docs = st.tuples(st.sampled_from(TYPES), st.sampled_from(NAMES), st.sampled_from(OWNERS), st.booleans())
attachments = st.one_of(
    st.none(),
    st.binary(max_size=16).map(lambda b: {"blob": b}),
    st.lists(st.floats(-1e6, 1e6), min_size=1, max_size=6).map(lambda v: {"hist": np.array(v)}),
)


def render(d) -> str:
    t, n, o, note = d
    owner = f' owner="{o}"' if o else ""
    head = f'<OBJECT type="{t}" name="{n}"{owner}'
    return head + "><NOTE>x</NOTE></OBJECT>" if note else head + "/>"


def same_attachments(got, want) -> bool:
    if set(got) != set(want):
        return False
    for k, v in want.items():
        g = got[k]
        if isinstance(v, np.ndarray):
            if not (isinstance(g, np.ndarray) and g.dtype == v.dtype and np.array_equal(g, v)):
                return False
        elif g != v:
            return False
    return True


class MemoryModel(RuleBasedStateMachine):
    """``persist``: run against a SQLite store and reload from it now and then."""

    persist = False
    ids = Bundle("ids")
    subs = Bundle("subs")

    @initialize()
    def start(self):
        self.dir = Path(tempfile.mkdtemp(prefix="hmem-")) if self.persist else None
        self.store = SqliteStore(self.dir / "m.sqlite") if self.persist else None
        self.memory = ActiveMemory("objects", store=self.store, indexes=INDEXES)
        self.model: dict[int, tuple] = {}
        self.model_att: dict[int, dict] = {}
        self.next_id = 1
        self.subs_model: dict[int, tuple[str, frozenset[str]]] = {}
        self.heard: list[tuple] = []
        self.expected: list[tuple] = []

    def teardown(self):
        if self.store is not None:
            self.store.close()
        if self.dir is not None:
            shutil.rmtree(self.dir, ignore_errors=True)

    def _expect(self, action: str, doc_id: int, new, old) -> None:
        for sid in sorted(self.subs_model):
            xp, actions = self.subs_model[sid]
            if action not in actions:
                continue
            m = XPATHS[xp](new)
            if m or (old is not None and XPATHS[xp](old)):
                self.expected.append((sid, action, doc_id, render(new), m))

    @rule(target=ids, d=docs, att=attachments)
    def insert(self, d, att):
        doc_id = self.memory.insert(render(d), att)
        assert doc_id == self.next_id
        self.next_id += 1
        self.model[doc_id] = d
        self.model_att[doc_id] = dict(att or {})
        self._expect("insert", doc_id, d, None)
        return doc_id

    @rule(doc_id=ids, d=docs, att=attachments)
    def update(self, doc_id, d, att):
        if doc_id not in self.model:
            with pytest.raises(MemoryQueryError):
                self.memory.update(doc_id, render(d))
            return
        old = self.model[doc_id]
        self.memory.update(doc_id, etree.fromstring(render(d)), att)
        self.model[doc_id] = d
        if att is not None:
            self.model_att[doc_id] = dict(att)
        self._expect("update", doc_id, d, old)

    @rule(doc_id=consumes(ids))
    def remove(self, doc_id):
        if doc_id not in self.model:
            with pytest.raises(MemoryQueryError):
                self.memory.remove(doc_id)
            return
        rec = self.memory.remove(doc_id)
        assert etree.tostring(rec.xml, encoding="unicode") == render(self.model[doc_id])
        self._expect("remove", doc_id, self.model.pop(doc_id), None)
        self.model_att.pop(doc_id)

    @rule(xp=st.sampled_from(sorted(XPATHS)))
    def free_query(self, xp):
        want = [i for i in sorted(self.model) if XPATHS[xp](self.model[i])]
        assert self.memory.query_ids(xp) == want
        assert [r.id for r in self.memory.query(xp)] == want

    @rule(t=st.sampled_from(TYPES), o=st.sampled_from(OWNERS), xp=st.one_of(st.none(), st.sampled_from(sorted(XPATHS))))
    def indexed_query(self, t, o, xp):
        where = {"type": t} if o is None else {"type": t, "owner": o}
        want = [i for i in sorted(self.model) if self.model[i][0] == t and (o is None or self.model[i][2] == o)
                and (xp is None or XPATHS[xp](self.model[i]))]
        assert self.memory.query_ids(xp, where=where) == want

    @rule(target=subs, xp=st.sampled_from(sorted(XPATHS)),
          actions=st.sets(st.sampled_from(("insert", "update", "remove")), min_size=1))
    def subscribe(self, xp, actions):
        sid = self.memory.subscribe(xp, lambda ev: self.heard.append(
            (ev.subscription, ev.action, ev.id, etree.tostring(ev.xml, encoding="unicode"), ev.matches)), actions=actions)
        self.subs_model[sid] = (xp, frozenset(actions))
        return sid

    @rule(sid=consumes(subs))
    def unsubscribe(self, sid):
        if sid in self.subs_model:
            self.memory.unsubscribe(sid)
            del self.subs_model[sid]
        else:
            with pytest.raises(MemoryQueryError):
                self.memory.unsubscribe(sid)

    @precondition(lambda self: self.persist)
    @rule()
    def reload(self):
        """A later run: a new store object and memory read what was committed (subscriptions do not survive)."""
        self.store.close()
        self.store = SqliteStore(self.dir / "m.sqlite")
        self.memory = ActiveMemory("objects", store=self.store, indexes=INDEXES)
        self.subs_model.clear()

    @invariant()
    def same_documents(self):
        if not hasattr(self, "memory"):
            return
        assert self.memory.ids() == sorted(self.model)
        for i, d in self.model.items():
            rec = self.memory.get(i)
            assert etree.tostring(rec.xml, encoding="unicode") == render(d)
            assert same_attachments(rec.attachments, self.model_att[i])

    @invariant()
    def subscribers_heard_exactly_what_concerned_them(self):
        if hasattr(self, "memory"):
            assert self.heard == self.expected


class PersistentMemoryModel(MemoryModel):
    persist = True


TestMemoryModel = MemoryModel.TestCase
TestMemoryModel.settings = settings(max_examples=examples(40, 400), stateful_step_count=30)
TestPersistentMemoryModel = PersistentMemoryModel.TestCase
TestPersistentMemoryModel.settings = settings(max_examples=examples(10, 100), stateful_step_count=30)


@settings(max_examples=examples(50, 300))
@given(st.lists(docs, max_size=20))
def test_returned_documents_are_copies_that_cannot_change_the_memory(ds):
    m = ActiveMemory("m", indexes=INDEXES)
    for d in ds:
        m.insert(render(d))
    for rec in m.query():
        rec.xml.set("type", "changed")
        rec.xml.append(etree.Element("EXTRA"))
    assert m.query_ids(where={"type": "changed"}) == []
    assert [etree.tostring(m.get(i).xml, encoding="unicode") for i in m.ids()] == [render(d) for d in ds]


def test_a_failed_change_changes_nothing():
    m = ActiveMemory("m", indexes=INDEXES)
    heard = []
    m.subscribe("/*", heard.append)
    a = m.insert('<OBJECT type="cup" name="a"/>')
    for bad in ("<OBJECT", '<!DOCTYPE x [<!ENTITY e "boom">]><x>&e;</x>', 42):
        with pytest.raises(MemoryQueryError):
            m.insert(bad)
        with pytest.raises(MemoryQueryError):
            m.update(a, bad)
    with pytest.raises(MemoryQueryError):
        m.insert("<x/>", {"o": np.array([object()])})
    with pytest.raises(MemoryQueryError, match="bad XPath"):
        m.query("//[")
    with pytest.raises(MemoryQueryError, match="no index"):
        m.query(where={"colour": "red"})
    assert m.ids() == [a] and len(heard) == 1
