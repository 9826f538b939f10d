"""flow7: no refusal a third time in a row (docs/semantics.md §4).

On main, a TV's "stay with us for the late film" heard while the robot looked around after a
good-bye got "Please look at me and say hello first." every seven seconds for two minutes
(studio_confirm_repeat seeds 7-9). The same refusal outside a sub-dialog is said at most twice in a
row: something else said, or a new supervisor state, makes it news again."""

from __future__ import annotations

from hypothesis import given, settings
from hypothesis import strategies as st
from lxml import etree

from robot.dialog.loader import BIRON_DIALOGS, load
from robot.dialog.manager import MAX_SAME_REFUSAL, DialogManager, Say

DOC = load(BIRON_DIALOGS)
HELLO_FIRST = "Please look at me and say hello first."


def _rejected(name: str, state: str) -> etree._Element:
    return etree.fromstring(f'<rejected event="dialog#1" name="{name}" reason="inapplicable" state="{state}" detail="d"><event name="{name}"/></rejected>')


def _says(outs) -> list[str]:
    return [o.text for o in outs if isinstance(o, Say)]


def test_the_tv_gets_say_hello_first_twice_then_silence():
    dm = DialogManager(DOC)
    dm.on_state("LookingAround")
    said = [_says(dm.on_rejected(_rejected(ev, "LookingAround"))) for ev in ("stop", "wait", "stop", "object_teaching", "stop")]
    assert said == [[HELLO_FIRST], [HELLO_FIRST], [], [], []]  # main: five times
    s = dm.summary()
    assert s["refusals_unsaid"] == 3 and s["rejections_explained"] == s["rejections"] == 5
    dm.on_state("Interacting")
    dm.on_state("LookingAround")  # a new interaction ended: news again
    assert _says(dm.on_rejected(_rejected("stop", "LookingAround"))) == [HELLO_FIRST]


STEPS = st.lists(st.one_of(
    st.tuples(st.just("reject"), st.sampled_from(["stop", "follow", "object_teaching"]),
              st.sampled_from(["LookingAround", "Following", "ObjectTeaching", "Navigating"])),
    st.tuples(st.just("state"), st.sampled_from(["LookingAround", "Interacting", "Following"]), st.just("")),
    st.tuples(st.just("frame"), st.just(""), st.just("")),
), max_size=30)


@settings(max_examples=300, deadline=None)
@given(steps=STEPS)
def test_no_refusal_three_times_in_a_row(steps):
    """Whatever comes in, the robot's speech never holds the same refusal three times in a row
    with no other sentence and no state change between; a refusal not said twice already is said."""
    dm = DialogManager(DOC)
    run: tuple[str, int] | None = None  # (refusal, times said in a row), as the robot's speech shows it
    for kind, what, state in steps:
        if kind == "state":
            if what != dm.es_state:
                run = None
            dm.on_state(what)
            continue
        if kind == "frame":
            outs = dm.on_frame(etree.fromstring('<not_understood start="0" end="1" confidence="0.5" reason="no parse">mumble</not_understood>'))
        else:
            if state != dm.es_state:
                run = None
            dm.on_state(state)
            text = DOC.rejection_text(what, "inapplicable", state)
            outs = dm.on_rejected(_rejected(what, state))
            if not dm.stack:  # outside a sub-dialog: the rule applies
                before = run[1] if run is not None and run[0] == text else 0
                assert (_says(outs) == [text]) == (before < MAX_SAME_REFUSAL)
        for t in _says(outs):
            run = (t, run[1] + 1) if run is not None and run[0] == t else (t, 1)
            assert run[1] <= MAX_SAME_REFUSAL or kind != "reject"
    s = dm.summary()
    assert s["rejections_explained"] == s["rejections"]
