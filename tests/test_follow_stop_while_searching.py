"""Her "stop" heard while the follower searches for her (her track unseen): she stays the partner, so the
follower's catch-up drives up to where it looks for her (face20), and the role never passes silently to a
bystander in view who never spoke (review20 F0/F1: a rule that let her track go handed the role to the last
potential partner or the selector's stale choice)."""
import types

from lxml import etree

from tests.test_follow_reacquire import SEEN, _following

GREEN = (0.1, 0.7, 0.1)


def _stop_while_searching(last_pp=None, selected=None):
    t = SEEN + 3.0
    a = _following([(2.0, 1.5, GREEN)], t)  # track 2: a bystander in other clothes, in view, silent
    a.sim = types.SimpleNamespace(now=t)
    a._follow_searching = SEEN + 0.5  # the follower's status says it searches
    if last_pp is not None:
        a._last_pp = last_pp
    a.selector = types.SimpleNamespace(selected=selected)  # the bottom-up selector's (stale) choice
    a.refused = []
    a._plan_sub = a._events_sub = a._caller = None
    a._stood = lambda now: False
    a._stood_stop_at = -1e9
    for m in ("_publish_state", "_listen_to_player", "_new_partner"):
        setattr(a, m, lambda *k, **kw: None)
    her = a.partner
    a._on_order(types.SimpleNamespace(xml=etree.Element("order", name="interact"), created=t))
    return a, her


def test_stop_while_searching_keeps_her_over_the_last_potential_partner():
    a, her = _stop_while_searching(last_pp=(2, 1.0))
    assert a.fsm.state == "Interaction"
    assert a.partner == her
    assert not a.partner_lost_sent


def test_stop_while_searching_keeps_her_over_a_stale_selection():
    a, her = _stop_while_searching(selected=2)
    assert a.fsm.state == "Interaction"
    assert a.partner == her
