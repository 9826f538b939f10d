""""Wrong" users (profile ``wrong``, ``<mistakes confirm= misname= self-correct=/>``): she says
yes to the robot's wrong guess, names what she teaches wrongly, and corrects herself at once;
a profile without mistakes draws nothing for them."""

from __future__ import annotations

import dataclasses

from homesim.scenario.loader import load_scenario_text
from homesim.sim import Simulation
from homesim.tour.stage import Stage
from homesim.tour.study import _user_wrong
from humans.phrasings import default_bank
from humans.profiles import default_profiles, draw_profile
from tests.stage_helpers import PEOPLE
from tests.world_helpers import ROOM

import numpy as np
import pytest

ROOM_TEXT = ROOM.read_text(encoding="utf-8")


def _stage(script: str, *, on: str = "", seed: int = 0, **mistakes: float) -> Stage:
    text = ROOM_TEXT.replace('torso="yellow"/>', f'torso="yellow">\n{on}\n<script>\n{script}\n</script>\n</human>')
    sc = load_scenario_text(text.replace('duration="10"', 'duration="30"'), source="wrong.xml")
    st = Stage(Simulation(seed=seed, scenario=sc.name), sc, actors=PEOPLE)
    ann = st.actors["ann"]
    ann.traits = dataclasses.replace(ann.traits, **mistakes)
    return st


def _said(st: Stage) -> list[str]:
    return [u.text for u in st.world.sound.by("ann")]


def test_the_wrong_profile_makes_mistakes_and_the_others_none():
    profiles = default_profiles()
    wrong = draw_profile(profiles["wrong"], np.random.default_rng(0))
    assert (wrong.confirm_wrongly, wrong.misname, wrong.self_correct) == (0.3, 0.3, 0.6)
    for name in ("typical", "cooperative", "impatient", "vague", "distracted", "silent"):
        t = draw_profile(profiles[name], np.random.default_rng(0))
        assert (t.confirm_wrongly, t.misname, t.self_correct) == (0.0, 0.0, 0.0), name


def test_she_says_yes_to_a_wrong_guess_instead_of_correcting_it():
    st = _stage('<wait for="20"/>', on='<on hears="^is this" max="2"><say request="correct" about="the living room"/></on>',
                confirm_wrongly=1.0)
    st.sim.call_at(1.0, lambda: st.world.sound.say("robot", "Is this the kitchen?", st.sim.now))
    st.run(10)
    (answer,) = _said(st)
    assert answer in {p.text for p in default_bank().phrasings("yes")}
    assert st.actors["ann"].confirmed_wrongly == 1


@pytest.mark.parametrize("correct", [1.0, 0.0])
def test_she_misnames_what_she_teaches_and_may_correct_herself_at_once(correct):
    st = _stage('<point object="cup" duration="2"/>\n<say text="Here you can see my red cup" request="teach-object" about="my red cup"/>\n'
                '<wait for="8"/>', misname=1.0, self_correct=correct)
    st.run(14)
    said = _said(st)
    words = default_bank().object_words
    wrong = said[0].removeprefix("Here you can see my red ")
    assert said[0] != "Here you can see my red cup" and wrong in {ws[0] for t, ws in words.items() if t != "cup"}
    ann = st.actors["ann"]
    assert ann.misnamed == 1 and ann.self_corrected == int(correct)
    if correct:
        assert len(said) == 2 and "my red cup" in said[1].lower()
        assert said[1] in {default_bank().render(p, "my red cup") for p in default_bank().phrasings("self-correct")}
    else:
        assert len(said) == 1


def test_a_user_without_mistakes_draws_nothing_for_them():
    st = _stage('<say text="Here you can see my red cup" request="teach-object" about="my red cup"/>\n<wait for="3"/>',
                on='<on hears="^is this" max="2"><say request="correct" about="my red cup"/></on>')
    st.sim.call_at(4.0, lambda: st.world.sound.say("robot", "Is this your book?", st.sim.now))
    st.run(12)
    assert _said(st)[0] == "Here you can see my red cup"
    assert not [k for k in st.sim._rngs if ":confirm:" in k or ":misname:" in k or ":self-correct:" in k]


def test_a_study_marks_failures_after_a_users_mistake():
    assert _user_wrong({"users.confirmed_wrongly": 1})
    assert _user_wrong({"users.misnamed": 2, "users.self_corrected": 1})
    assert not _user_wrong({"users.misnamed": 1, "users.self_corrected": 1})
    assert not _user_wrong({})


def test_a_misnamed_room_is_another_room_of_her_home_and_a_misnamed_thing_another_type():
    from types import SimpleNamespace

    from humans.profiles import Traits
    from humans.script import Actor

    rooms = tuple(SimpleNamespace(name=n) for n in ("kitchen", "living room", "bedroom"))
    world = SimpleNamespace(scenario=SimpleNamespace(rooms=rooms))
    ann = Actor(world, "ann", (), traits=Traits(misname=1.0), rng=np.random.default_rng(5))  # type: ignore[arg-type]
    rooms_said = {ann.misnaming("the living room", "misname:1") for _ in range(40)}
    assert rooms_said == {"the kitchen", "the bedroom"}
    words = default_bank().object_words
    type_of = {w: t for t, ws in words.items() for w in ws}
    for _ in range(40):
        wrong = ann.misnaming("my favourite mug", "misname:2")
        assert wrong is not None and wrong.startswith("my favourite ") and type_of[wrong[13:]] != "cup"
    assert ann.misnaming("it", "misname:3") is None  # nothing she could name wrongly
    careful = Actor(world, "bo", (), traits=Traits(misname=0.0), rng=np.random.default_rng(5))  # type: ignore[arg-type]
    assert careful.misnaming("the kitchen", "misname:1") is None
