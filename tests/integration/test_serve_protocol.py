"""The order of ``auvplan serve``'s splices: whatever order the answers arrive in (reordered, dropped,
answered after a later edit), the page's copy is always a state the server had under that revision, and
asking for the state once more makes it the server's current state.  Oracle: the server's own record of
what each revision was.  Both the page's rule (``static/delta.js``, run in node) and its Python twin
(:func:`auvplan.serve.delta.take`) are driven with the same answers; no browser."""

from __future__ import annotations

import json
import shutil
import subprocess
from importlib import resources

import numpy as np
import pytest

from auvplan.serve.delta import PageCopy, Revisions, StaleRevision, take

_DELTA_JS = resources.files("auvplan.serve") / "static" / "delta.js"


def _json(st):
    """An answer as the page receives it (numpy arrays as lists)."""
    return json.loads(json.dumps(st, default=lambda a: a.tolist()))


def _violations(w):
    """Stand-in violations that follow the waypoints (one per leg that climbs above -2 000 m)."""
    return [{"leg": i, "kind": "altitude", "value": float(w[i + 1, 2])} for i in range(len(w) - 1)
            if w[i + 1, 2] > -2000.0]


class _Server:
    """Waypoints edited by index, a :class:`Revisions`, and the record of what every revision was."""

    def __init__(self, rng):
        self.rng = rng
        self.w = np.column_stack([np.arange(30.0), np.zeros(30), np.full(30, -2100.0)])
        self.rev = Revisions()
        self.seen = {}

    def edit(self, known=None):
        """One random move, insert or delete (refused when ``known`` is stale)."""
        self.rev.require(known, self.w, _violations(self.w))
        k = int(self.rng.integers(1, len(self.w) - 1))
        op = self.rng.choice(["move", "insert", "delete"])
        if op == "move":
            self.w = self.w.copy()
            self.w[k] += self.rng.normal(0.0, 200.0, 3)
        elif op == "insert":
            self.w = np.insert(self.w, k, self.w[k] + 0.5, axis=0)
        elif len(self.w) > 3:
            self.w = np.delete(self.w, k, axis=0)

    def answer(self, known):
        st = self.rev.state(self.w, _violations(self.w), known)
        self.seen[st["rev"]] = (self.w.tolist(), _json(_violations(self.w)))
        st["check"] = {"violations": _violations(self.w)}
        return _json(st)


def _node_take(answers):
    """The page's rule (delta.js) run in node on the answers in order: each outcome and the copy after it."""
    script = (f"{_DELTA_JS.read_text(encoding='utf-8')}\n"
              "const answers = JSON.parse(require('fs').readFileSync(0, 'utf8'));\n"
              "const copy = {rev: null, w: [], v: []}; const out = [];\n"
              "for (const a of answers) { const r = takeState(copy, a);"
              " out.push([r, copy.rev, JSON.parse(JSON.stringify(copy.w)), JSON.parse(JSON.stringify(copy.v))]); }\n"
              "process.stdout.write(JSON.stringify(out));\n")
    done = subprocess.run(["node", "-e", script], input=json.dumps(answers), capture_output=True, text=True,
                          check=True, timeout=60)
    return json.loads(done.stdout)


def _py_take(answers, rule=take):
    page, out = PageCopy(), []
    for a in answers:
        r = rule(page, a)
        out.append([r, page.rev, [list(p) for p in page.waypoints], list(page.violations)])
    return out


def _scramble(seed):
    """A first whole state, then rounds of 1-3 edits sent on the same revision, answered after all of the
    round's edits ran, delivered shuffled with some dropped; the page re-asks (``known``) per round."""
    rng = np.random.default_rng(seed)
    server = _Server(rng)
    answers = [server.answer(None)]
    known = answers[0]["rev"]
    for _ in range(12):
        n = int(rng.integers(1, 4))
        for _ in range(n):
            server.edit()  # edits from scripts (no rev) interleave with the page's requests
        round_answers = [server.answer(known) for _ in range(n)]
        if rng.random() < 0.5:
            server.edit()
            round_answers.append(server.answer(known))
        order = rng.permutation(len(round_answers))
        kept = [round_answers[i] for i in order if rng.random() > 0.2]
        answers += kept
        known = max([known] + [a["rev"] for a in kept])
    answers.append(server.answer(None))  # the page asks for the whole state once more
    return server, answers


def _check_trace(server, answers, trace):
    kinds = set()
    for a, (outcome, rev, w, v) in zip(answers, trace):
        kinds.add(outcome)
        if rev is not None:  # the copy is exactly what the server had under that revision
            assert (w, v) == server.seen[rev], (outcome, a["rev"], rev)
    assert trace[-1][0] == "ok" and trace[-1][2] == server.w.tolist()  # and ends on the current state
    return kinds


@pytest.mark.parametrize("seed", range(6))
def test_reordered_and_dropped_answers_never_leave_the_page_on_a_state_the_server_did_not_have(seed):
    server, answers = _scramble(seed)
    kinds = _check_trace(server, answers, _py_take(answers))
    assert {"ok", "gap"} <= kinds  # splices applied and splices refused both happen


@pytest.mark.skipif(shutil.which("node") is None, reason="node is not installed")
def test_the_pages_rule_in_delta_js_is_the_same_rule():
    for seed in range(6):
        server, answers = _scramble(seed)
        trace = _node_take(answers)
        _check_trace(server, answers, trace)
        assert trace == _py_take(answers)  # the page and its Python twin, outcome by outcome


def test_two_edits_answered_on_one_revision_are_not_spliced_twice():
    """The failure seen in the browser: two inserts on revision r, both answered after both ran; the
    second answer's splice is on r, not on the r + 1 the page then holds, so it is refused (gap)."""
    server = _Server(np.random.default_rng(0))
    page = PageCopy()
    assert take(page, server.answer(None)) == "ok"
    r = page.rev
    server.w = np.insert(server.w, 5, [5.5, 0.0, -2100.0], axis=0)
    server.w = np.insert(server.w, 9, [8.5, 0.0, -2100.0], axis=0)
    a, b = server.answer(r), server.answer(r)
    assert a["delta"]["base"] == b["delta"]["base"] == r and a["rev"] == b["rev"] == r + 1
    assert take(page, a) == "ok" and page.waypoints == server.w.tolist()
    assert take(page, b) == "gap" and page.rev is None  # the page re-asks for everything
    assert take(page, server.answer(page.rev)) == "ok" and page.waypoints == server.w.tolist()


def test_an_edit_on_a_stale_revision_is_refused():
    server = _Server(np.random.default_rng(1))
    r = server.answer(None)["rev"]
    server.edit(r)  # on the current revision: applied
    before = server.w.copy()
    with pytest.raises(StaleRevision, match=f"rev {r}: the mission changed"):
        server.edit(r)  # the page has not seen the first edit's answer: its index may name another waypoint
    np.testing.assert_array_equal(server.w, before)
    server.edit(None)  # a script without a revision is not checked
