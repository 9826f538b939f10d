"""The type an object is stored as (issue 26, fresh3 passage_talk_aside / angle_long_tour: her
toaster was stored as a stove, the lexicon's class for the word): the user's word when the camera
saw the object as just that, else the speech frame's type, else what the camera saw most."""

from __future__ import annotations

from hypothesis import given
from hypothesis import strategies as st

from robot.objects.resolve import COLOURS, Candidate, Wanted, learned_type


def _seen(counts: dict[str, int]) -> Candidate:
    c = Candidate(1.0, 1.0, 0.9)
    for t, k in sorted(counts.items()):
        for _ in range(k):
            c.add(t, 1.0, 1.0, 0.9, COLOURS["grey"])
    return c


def test_her_toaster_is_a_toaster_not_the_lexicons_stove():
    assert learned_type(_seen({"toaster": 9, "radio": 1}), Wanted(type="stove", name="toaster")) == "toaster"


def test_a_word_the_camera_has_no_class_for_keeps_the_frames_type():
    # "lemon tree": the camera sees a plant; "mug": the camera sees a cup
    assert learned_type(_seen({"plant": 10}), Wanted(type="plant", name="lemon tree")) == "plant"
    assert learned_type(_seen({"cup": 10}), Wanted(type="cup", name="mug")) == "cup"


def test_a_two_word_name_is_the_cameras_class_with_an_underscore():
    assert learned_type(_seen({"remote_control": 6}), Wanted(type="remote_control", name="remote control")) == "remote_control"
    assert learned_type(_seen({"washing_machine": 6}), Wanted(type="appliance", name="washing machine")) == "washing_machine"


def test_without_a_frame_type_the_camera_decides():
    assert learned_type(_seen({"vase": 4, "bowl": 1}), Wanted()) == "vase"


@given(st.dictionaries(st.sampled_from(["toaster", "stove", "radio", "plant", "lemon_tree"]), st.integers(1, 12), min_size=1),
       st.sampled_from(["stove", "plant", ""]), st.sampled_from(["toaster", "stove", "lemon tree", "radio", ""]))
def test_the_stored_type_is_her_word_or_a_class_the_camera_or_the_lexicon_gave(counts, typ, name):
    # review12 item 7: invariants, not the formula again. The stored type is never made up: it is her word,
    # the frame's (lexicon) class or a class the camera saw. Her word is taken only when the camera saw it,
    # and always when the camera saw nothing else.
    c = _seen(counts)
    got = learned_type(c, Wanted(type=typ, name=name))
    word = "_".join(name.split())
    assert got in {word, typ} | set(counts)
    if got == word and word != typ:
        assert counts.get(word, 0) > 0  # the camera saw it as her word
    if word and set(counts) == {word}:
        assert got == word  # every detection says her word: her toaster is a toaster
    if not typ and not word:
        assert got == max(counts, key=lambda t: (counts[t], t)) or counts[got] == max(counts.values())
