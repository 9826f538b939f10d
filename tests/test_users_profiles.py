"""User profiles: seeded draws within their declared bounds, the same person for the same seed."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from homesim.errors import InputError
from homesim.scenario.loader import load_scenario_text
from homesim.scenario.wordpattern import PatternError, compile_words
from homesim.sim import Simulation
from homesim.tour.stage import Stage
from humans.phrasings import STYLES, default_bank
from humans.profiles import NUMERIC, default_profiles, draw_profile, load_profiles, traits_for
from tests.test_users_reactive import _text
from tests.stage_helpers import ACTORS, PEOPLE

PROFILES = sorted(default_profiles())


@settings(max_examples=60, deadline=None)
@given(name=st.sampled_from(PROFILES), seed=st.integers(0, 2**32 - 1))
def test_a_draw_lies_within_the_profiles_declared_bounds(name, seed):
    p = default_profiles()[name]
    t = draw_profile(p, np.random.default_rng(seed))
    for key, attr in (("voice", "voice"), ("distance", "distance"), ("speed", "speed"), ("off-axis", "off_axis"), ("pointing-error", "pointing_error")):
        d = p.numeric[key]
        assert d.low <= getattr(t, attr) <= d.high
    assert p.numeric["patience"].low <= t.patience <= p.numeric["patience"].high
    assert set(t.repairs) <= {s for s, _ in p.repairs}
    assert t.give_up in {s for s, w in p.give_up if w > 0}


@settings(max_examples=30, deadline=None)
@given(name=st.sampled_from(PROFILES), seed=st.integers(0, 10_000), who=st.sampled_from(["ann", "bob"]))
def test_same_seed_same_person_and_one_persons_draws_do_not_shift_anothers(name, seed, who):
    def traits(s: int, extra: bool):  # type: ignore[no-untyped-def]
        sim = Simulation(seed=s)
        if extra:
            sim.rng("human:zoe").random(5)  # someone else drawing first changes nothing for her
        spec = dataclasses.replace(_spec(), name=who, profile=name)
        return traits_for(spec, sim.rng(f"human:{who}"))
    assert traits(seed, False) == traits(seed, True)


def test_an_override_replaces_its_trait_and_leaves_the_others_as_drawn():
    spec = dataclasses.replace(_spec(), profile="typical")
    a = traits_for(spec, Simulation(seed=3).rng("human:ann"))
    b = traits_for(dataclasses.replace(spec, traits=(("voice", "70"), ("repairs", "none"))), Simulation(seed=3).rng("human:ann"))
    assert b.voice == 70.0 and b.repairs == ()
    assert dataclasses.replace(b, voice=a.voice, repairs=a.repairs) == a


def test_populations_differ_the_way_their_names_say():
    rng = np.random.default_rng(0)
    draws = {n: [draw_profile(default_profiles()[n], rng) for _ in range(300)] for n in PROFILES}
    mean = lambda n, f: float(np.mean([getattr(t, f) for t in draws[n]]))  # noqa: E731
    assert mean("impatient", "patience") < mean("typical", "patience") < mean("cooperative", "patience")
    assert mean("silent", "voice") < mean("typical", "voice") - 5
    assert mean("distracted", "off_axis") > 3 * mean("typical", "off_axis")
    assert mean("vague", "pointing_error") > 2 * mean("cooperative", "pointing_error")
    assert mean("distracted", "distance") > 1.2  # Hall's social zone, not the personal one


def test_a_person_with_a_profile_speaks_at_her_drawn_level_and_walks_at_her_drawn_speed():
    sc = load_scenario_text(_text('<say request="greet"/>', attrs='profile="typical"'), source="p.xml")
    sim = Simulation(seed=5, scenario=sc.name)
    stage = Stage(sim, sc, actors=PEOPLE)
    stage.run(5)
    ann = stage.actors["ann"]
    (u,) = stage.world.sound.by("ann")
    assert u.loudness == ann.traits.voice and 52 <= u.loudness <= 68
    assert stage.world.humans["ann"].speed == ann.traits.speed
    assert u.text in {p.text for p in default_bank().phrasings("greet")}


def test_without_a_profile_nothing_is_drawn():
    sim = Simulation(seed=1)
    t = traits_for(_spec(), None)
    assert (t.voice, t.distance, t.speed, t.off_axis, t.pointing_error) == (60.0, 0.9, None, 0.0, 0.0)
    assert "human:ann" not in sim._rngs


def test_every_request_has_many_phrasings_in_several_styles():
    bank = default_bank()
    for name, ps in bank.requests.items():
        assert len(ps) >= 5, name
        assert len({p.style for p in ps}) >= 3, name
        assert {p.style for p in ps} <= set(STYLES)


def test_a_bad_profile_file_is_refused_with_its_line(tmp_path):
    f = tmp_path / "p.xml"
    f.write_text('<profiles>\n<profile name="x">\n<voice normal="60 3"/>\n</profile>\n</profiles>\n')
    with pytest.raises(InputError, match="min= and max=") as err:
        load_profiles(f)
    assert err.value.line == 3


PROFILE = """<profiles>
<profile name="x">
<voice fixed="60"/><distance fixed="0.9"/><speed fixed="1.2"/>
{patience}
<off-axis fixed="0"/><pointing-error fixed="0"/><give-up skip="1"/>
</profile>
</profiles>
"""


def test_patience_bounds_between_whole_numbers_are_refused_with_the_line(tmp_path):
    # a patience of 0.4 to 0.6 repairs was accepted and every draw rounded out of it (0 or 1)
    f = tmp_path / "p.xml"
    f.write_text(PROFILE.format(patience='<patience normal="0.5 0.3" min="0.4" max="0.6"/>'))
    with pytest.raises(InputError, match="whole") as err:
        load_profiles(f)
    assert err.value.line == 4
    f.write_text(PROFILE.format(patience='<patience uniform="1 3"/>'))
    p = load_profiles(f)["x"]
    assert {draw_profile(p, np.random.default_rng(s)).patience for s in range(40)} <= {1, 2, 3}


def test_a_trait_given_twice_is_refused_with_the_second_line(tmp_path):
    # the second <voice> was silently ignored: the author's 80 dB user spoke at 60
    f = tmp_path / "p.xml"
    f.write_text(PROFILE.format(patience='<patience fixed="1"/>\n<voice fixed="80"/>'))
    with pytest.raises(InputError, match="<voice> twice") as err:
        load_profiles(f)
    assert err.value.line == 5


def test_phrasing_weights_all_zero_are_refused_with_the_line(tmp_path):
    # plain="0" was accepted and every style then drawn alike
    f = tmp_path / "p.xml"
    f.write_text(PROFILE.format(patience='<patience fixed="1"/>\n<phrasing plain="0" terse="0"/>'))
    with pytest.raises(InputError, match="positive weight") as err:
        load_profiles(f)
    assert err.value.line == 5


def test_every_numeric_trait_has_bounds_in_range():
    for p in default_profiles().values():
        for key, d in p.numeric.items():
            lo, hi = NUMERIC[key]
            assert lo <= d.low <= d.high <= hi


# ------------------------------------------------------------------ word patterns
WORDS = st.sampled_from(["is", "this", "the", "kitchen", "cup", "yes", "no", "which", "one", "i"])


@settings(max_examples=200, deadline=None)
@given(words=st.lists(WORDS, min_size=1, max_size=4), before=st.lists(WORDS, max_size=5), after=st.lists(WORDS, max_size=5))
def test_a_literal_word_pattern_matches_any_utterance_that_contains_its_words(words, before, after):
    p = compile_words(" ".join(words))
    assert p.search(" ".join(before + words + after).capitalize() + "?")
    assert p.search(" ".join(before + after)) == (" ".join(words) in " ".join(before + after) and _contains(before + after, words))


def _contains(hay: list[str], needle: list[str]) -> bool:
    return any(hay[i:i + len(needle)] == needle for i in range(len(hay) - len(needle) + 1))


@settings(max_examples=200, deadline=None)
@given(text=st.text(max_size=40))
def test_any_pattern_text_compiles_or_is_refused_with_a_column(text):
    try:
        compile_words(text)
    except PatternError as exc:
        assert 1 <= exc.column <= max(len(text), 1) + 1 or exc.column == 500


def test_patterns_on_long_utterances_stay_cheap():
    p = compile_words("* * a * b * c * d $".replace("* *", "*"))
    assert not p.search(" ".join(["a", "b", "c"] * 400))
    assert compile_words("(is|was) this _ room").search("Is this the living room?") is False
    assert compile_words("(is|was) this [the] _ room").search("Is this the living room?")
    assert compile_words("(is|was) this [the] * room").search("Is this the living room?")
    assert compile_words("^which one").search("Which one do you mean?")
    assert not compile_words("^one").search("Which one do you mean?")


def test_words_of_any_script_are_words_and_columns_count_the_authors_characters():
    # letters outside ASCII are letters: 'zoë' is one word, not 'zo' and a refusal
    assert compile_words("zoë's room").search("This is Zoë's room.")
    assert not compile_words("zo").search("This is Zoë's room.")
    assert compile_words("KÜCHE").search("Das ist die Küche")
    # 'İ' lower-cases to two characters: the column still points at the author's '?'
    with pytest.raises(PatternError) as err:
        compile_words("İİİ ?")
    assert err.value.column == 5 and "'?'" in str(err.value)


def test_a_match_everything_alternative_is_seen_behind_many_others():
    # 65 alternatives before '*': the pattern still matches whatever the robot says
    p = compile_words("|".join(["yes"] * 65) + "|*")
    assert p.search("anything at all")
    assert () in p.phrases()


def _spec():  # type: ignore[no-untyped-def]
    sc = load_scenario_text(_text(""), source="p.xml")
    return sc.humans[0]


def test_nothing_of_her_profile_reaches_the_robots_bus():

    sc = load_scenario_text(_text('<wait for="1"/>\n<face robot="true"/>\n<say request="greet"/>\n<point object="cup" duration="1"/>',
                                  attrs='profile="distracted" patience="2"'), source="p.xml")
    sim = Simulation(seed=2, scenario=sc.name)
    stage = Stage(sim, sc, actors=ACTORS, keep_messages=True)
    stage.run(6)
    assert stage.messages
    text = " ".join(m.text() for m in stage.messages).lower()
    traits = stage.actors["ann"].traits
    for word in ("distracted", "profile", "patience", "off-axis", "pointing-error"):
        assert word not in text, word
    assert f"{traits.voice:.6f}" not in text


def _transcript(seed: int) -> list[tuple[float, str, float]]:
    sc = load_scenario_text(_text('<say request="greet"/>\n<wait-for hears="hello" timeout="2"/>\n<say request="follow"/>\n'
                                  '<wait-for hears="following" timeout="2"/>', attrs='profile="vague"'), source="p.xml")
    stage = Stage(Simulation(seed=seed, scenario=sc.name), sc, actors=PEOPLE)
    stage.run(30)
    return [(u.start, u.text, u.loudness) for u in stage.world.sound.by("ann")]


def test_the_same_seed_replays_the_same_user_word_for_word():
    assert _transcript(4) == _transcript(4)
    assert len({tuple(_transcript(s)) for s in range(4)}) > 1  # and other seeds give other users


def _tour(seed: int, on: str) -> list[str]:
    script = "\n".join(f'<wait for="2"/>\n<say request="{r}" about="the kitchen"/>' for r in ("greet", "teach-place", "follow", "teach-place", "goodbye"))
    sc = load_scenario_text(_text(script + '\n<point object="cup" duration="30"/>', attrs='profile="distracted"', on=on, duration=40), source="p.xml")
    stage = Stage(Simulation(seed=seed, scenario=sc.name), sc, actors=PEOPLE)
    stage.sim.call_at(0.5, lambda: stage.world.sound.say("robot", "Shall I follow you?", stage.sim.now))
    stage.run(35)
    ann = stage.actors["ann"]
    said = {u.start: u.text for u in stage.world.sound.by("ann")}
    looks = {t: d for t, _, d in ann.log if d.startswith("speaks looking")}
    pointing = stage.world.humans["ann"].pointing
    assert pointing is not None  # still pointing at the end
    return [f"{said[t]} / {looks.get(t, 'to the robot')}" for t in sorted(said) if said[t] != "Yes, I do"] + [f"{pointing.target[0]:.9f} {pointing.target[1]:.9f}"]


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_a_reaction_that_fires_does_not_change_the_rest_of_her_tour(seed):
    # one draw stream for all her acts: one answer "Yes, I do" (3 draws for looking away) changed
    # 6 to 7 of her 8 later phrasings; now every act of hers draws from its own stream
    assert _tour(seed, "") == _tour(seed, '<on hears="shall i follow you" max="5"><say text="Yes, I do"/></on>')


def test_normal_traits_are_truncated_not_piled_on_their_bounds_and_distracted_users_keep_a_social_distance():
    import numpy as np

    profiles = default_profiles()
    rng = np.random.default_rng(7)
    for name in ("typical", "impatient", "distracted"):
        dist = profiles[name].numeric["distance"]
        draws = np.array([dist.draw(rng) for _ in range(4000)])
        assert ((draws == dist.low) | (draws == dist.high)).mean() < 0.001, name  # clipping put 2 % exactly on a bound
    social = np.array([profiles["distracted"].numeric["distance"].draw(rng) for _ in range(2000)])
    assert social.min() >= 1.2  # Hall's social zone, as docs/users.md says
