"""2 000 calls with mutated arguments: each returns a result or raises rotorshunt.Error
(the command line's message), never another exception, a panic or a crash."""

import math
import random

import numpy as np
import pytest

import rotorshunt as rs

CASES = 2000

NUMBERS = [math.nan, math.inf, -math.inf, -1, -1e300, 0, 0.0, 1e-300, 1e300, 2**70, -(2**70), True, "1", "x", None,
           [1], {}, object(), np.float64(np.nan), np.int64(-3), complex(1, 1), b"1", 1000.0, 0.3, 1230]
COUNTS = [0, -1, -(2**63), 2**64, 1.5, "4", None, True, math.nan, np.int64(2), 3, 10001, [], 1]
SEQUENCES = [[], [math.nan], [-1.0, 1000.0], [1000.0, "a"], "1000:1100", 5, None, {"a": 1}, [[1000.0]],
             np.array([]), np.array([1000.0, 1001.0]), np.array([[1.0]]), np.array(["a"]), (1000.0, math.inf),
             range(1000, 1002), [1e300], [0.0], [0.1, 0.2], [1000, 1400], [1400, 1000], [10**400 if False else 1e308]]
NODES = [[], [-1], [16], [10**30], ["16"], "16", None, [1.5], [True], np.array([16]), [0, 64], [65]]
KEYS = ["speed", "circuit.state", "shaft.colour", "rings[0].eta", "analysis.reduced_modes", "", "=", "a.b.c",
        "circuit.branches[9].resistance", "design.starts", "version", "analysis.method", "disks[0].node"]
VALUES = [1, -1, 0, math.nan, "open", "closed", "x", True, [1, 2], {"a": 1}, 1e300, None, object(), 2**70]


def settings(r):
    if r.random() < 0.2:
        return [r.choice(["speed=1", "speed", "=3", "a.b=", "speed=nan", "circuit.state=open"])]
    return {r.choice(KEYS): r.choice(VALUES) for _ in range(r.randint(0, 3))}


def test_fuzz_the_api():
    r = random.Random(31)
    base = rs.Problem.from_file("problems/fig11-closed-2000.toml")
    text = open("problems/fig11-closed-2000.toml").read()
    outcomes = {"ok": 0, "error": 0}
    kinds = set()
    for case in range(CASES):
        n = lambda: r.choice(NUMBERS)
        calls = [
            lambda: base.modes(speed=n(), count=r.choice(COUNTS)),
            lambda: base.floquet(n(), n()),
            lambda: base.chart(r.choice(SEQUENCES), r.choice(SEQUENCES)),
            lambda: base.regions(r.choice(SEQUENCES), n(), n()),
            lambda: base.band(n(), n(), r.choice(SEQUENCES)),
            lambda: base.unbalance(r.choice(SEQUENCES), r.choice(NODES)),
            lambda: base.campbell(r.choice(SEQUENCES), count=r.choice(COUNTS)),
            lambda: base.with_set(settings(r)),
            lambda: rs.Problem.from_file(r.choice(["problems/paper-open.toml", "", "/", "no.toml", 3, None]), set=settings(r)),
            lambda: rs.Problem.from_toml(mutate(r, text)),
        ]
        call = r.choice(calls)
        try:
            call()
            outcomes["ok"] += 1
        except rs.Error as e:
            outcomes["error"] += 1
            kinds.add(type(e).__name__)
            assert str(e), "an error with no message"
        except Exception as e:  # noqa: BLE001 - the point of the test
            pytest.fail(f"case {case}: {type(e).__name__}: {e}")
    print(f"\n{CASES} cases: {outcomes['ok']} results, {outcomes['error']} errors of kinds {sorted(kinds)}")
    assert outcomes["ok"] + outcomes["error"] == CASES
    assert outcomes["error"] > CASES // 2


def mutate(r, text):
    b = bytearray(text.encode())
    for _ in range(r.randint(1, 4)):
        op = r.random()
        i = r.randrange(len(b))
        if op < 0.4:
            b[i] = r.choice(b"0123456789.-=[]\"\n eE#x")
        elif op < 0.7:
            del b[i : i + r.randint(1, 20)]
        else:
            b[i:i] = r.choice([b"nan", b"-", b"1e400", b"\n[x]\n", b"9" * 30, b"\x00"])
    return b.decode("utf-8", errors="replace")
