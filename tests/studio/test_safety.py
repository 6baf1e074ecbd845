"""The studio's guards: the session token, confined paths, checked websocket messages."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from sar_framework.studio.safety import (
    MESSAGE_MAX_BYTES,
    RefusedError,
    confine,
    new_token,
    parse_message,
    token_ok,
)


def test_tokens_are_fresh_and_compared_exactly() -> None:
    token = new_token()
    assert len(token) == 48 and token != new_token()
    assert token_ok(token, token)
    assert not token_ok(None, token)
    assert not token_ok(token[:-1], token)
    assert not token_ok("", token)


def test_paths_stay_inside_the_roots(tmp_path: Path) -> None:
    root = tmp_path / "project"
    (root / "trees").mkdir(parents=True)
    (tmp_path / "secret").write_text("x")
    (root / "link").symlink_to(tmp_path / "secret")
    assert confine("trees", [root]) == (root / "trees").resolve()
    assert confine(root / "trees" / "new.yaml", [root]) == (root / "trees" / "new.yaml")
    for outside in ("../secret", str(tmp_path / "secret"), "link", "trees/../../secret"):
        with pytest.raises(RefusedError, match="outside the directories open to the studio"):
            confine(outside, [root])
    with pytest.raises(RefusedError, match="no directory"):
        confine("x", [])


def test_known_messages_pass() -> None:
    assert parse_message('{"op": "seek", "t": 12.5}') == {"op": "seek", "t": 12.5}
    assert parse_message(b'{"op": "node", "uid": "0.1"}')["uid"] == "0.1"
    assert parse_message('{"op": "hello"}') == {"op": "hello"}


@pytest.mark.parametrize(("text", "why"), [
    ("not json", "not JSON"),
    ("[1, 2]", "a message is a JSON object"),
    ('{"t": 1}', "unknown op None"),
    ('{"op": "rm -rf"}', "unknown op 'rm -rf'"),
    ('{"op": "seek"}', "t missing"),
    ('{"op": "seek", "t": "soon"}', "t missing or of the wrong type"),
    ('{"op": "seek", "t": true}', "wrong type"),
    ('{"op": "seek", "t": 1e999}', "must be finite"),
    ('{"op": "seek", "t": 1, "path": "/etc"}', "unknown field"),
    ('{"op": "node", "uid": 7}', "wrong type"),
    (json.dumps({"op": "node", "uid": "x" * 500}), "too long"),
    (b"\xff\xfe", "not JSON"),
    ("x" * (MESSAGE_MAX_BYTES + 1), "at most"),
])
def test_malformed_messages_are_refused_with_a_reason(text: str | bytes, why: str) -> None:
    with pytest.raises(RefusedError, match=why.replace("(", r"\(")):
        parse_message(text)
