#!/usr/bin/env python3
"""Normalise and compare two output trees of scripts/compare-outputs.sh, file by file.

Usage: compare.py BASE_DIR HEAD_DIR

Every file of either tree is compared with its namesake in the other. PNG files are
compared as bytes. Every other file is read as UTF-8 text (bytes that are not UTF-8 are
kept as escapes, so they still compare exactly), the normalisations below are applied to
both sides alike, and the results must be equal. Exit 0 when all files are equal, 1 when
any differs or exists on one side only.

Normalisations: wall-clock times and the tool version only; every other byte, and every
number that describes a result, is compared as written. Each rule is anchored on the text
around the value, so it cannot reach a result:

  tool-version   `rotorshunt 0.1.0` (JSON "tool", report.md, the tuned.toml header, the
                 study manifests, `--version`) -> `rotorshunt <VERSION>`: provenance,
                 expected to change with a release while results do not.
  json-seconds   a JSON line `"seconds": <number>` -> `"seconds": <WALL>`: wall time of
                 `regions` and `band` (--json and regions.json), the design report's
                 optimiser and verification costs, study case results and summary.json.
                 Every field named `seconds` in the outputs is a wall time.
  task-pid       a JSON line `"pid": <digits>` inside a study case's `task` record
                 (result.json, summary.json) -> `"pid": <PID>`: the process that ran the
                 case. The host is the same machine on both sides; a Slurm job id appears
                 only under Slurm.
  regions-wall   `monodromy evaluations in 0.28 s` (regions text) -> `in <WALL> s`.
  band-wall      `(184 evaluations, 0.072 s)` (band text) -> `(184 evaluations, <WALL> s)`;
                 the evaluation count is kept.
  chart-timing   `timing: 231 points in 0.044 s wall (384.2 us/point/thread, 2 threads, ...`
                 (chart --timing) -> the wall time and the time per point replaced, the
                 point count, thread count, method and steps kept.
  design-wall    `..., 16.2 s optimising; verification 32008 evaluations, 9.6 s;` (design
                 text) -> both times replaced, the counts kept.
  report-cost    `- cost: 102 candidate designs, 34021 + 32008 Floquet (monodromy)
                 evaluations (optimiser + verification), 3.4 s + 2.3 s` (report.md;
                 `<li>cost: …` in report.html; older reports end `…, 16.2 s`) -> the
                 times replaced, the counts kept.
  study-wall     `study: 12 cases (12 run, ...) in 14.2 s;` (study text) -> the time
                 replaced.
  table-seconds  the cells of a column headed exactly `seconds` in a CSV file (first line
                 the header) or a Markdown table (study summary.csv and summary.md: wall
                 time of each case) -> `<WALL>`.

  owned-hash     in an output folder's ownership record `.rotorshunt-out.json`, the
                 sha256 of a file it lists -> `<SHA256 OF NAME>`, only where it is the
                 hash of that file's bytes in the same folder (a wrong hash still
                 differs). The file itself is compared on its own, normalised, so its
                 hash only repeats that comparison; left as written, it would differ
                 with every wall time inside the file (regions.json, report.*).

  owned-token    in an output folder's ownership record `.rotorshunt-out.json`, the
                 run-unique random token (`"token": "<24 hex digits>"`) -> `<TOKEN>`: it
                 is new on every run by design (what the tool removes it proves it wrote).

  progress-line  a whole line of standard error starting `progress: ` (the CLI's progress
                 on a non-terminal: from a run's fifth second on, every 5 s and at each
                 phase) -> removed: how many there are, and their counts and times,
                 depend on the machine's speed; the results are in the other files.

Progress bars are not normalised: the CLI draws them only on a terminal, and standard
error is a file here. Paths need no rule: both binaries run in the same directory with the
same relative arguments, so absolute paths (the study manifests) are equal.
"""

import csv
import hashlib
import io
import re
import sys
from pathlib import Path

WALL = "<WALL>"
NUM = r"[0-9][0-9.eE+-]*"

# (name, compiled pattern, replacement); applied in this order to every text file.
RULES = [
    ("tool-version", re.compile(r"\brotorshunt \d+\.\d+\.\d+[0-9A-Za-z.+-]*"), "rotorshunt <VERSION>"),
    ("json-seconds", re.compile(r'^(\s*"seconds": )' + NUM + r"(,?)$", re.M), r"\g<1>" + WALL + r"\g<2>"),
    ("task-pid", re.compile(r'^(\s*"pid": )\d+(,?)$', re.M), r"\g<1><PID>\g<2>"),
    ("owned-token", re.compile(r'^(\s*"token": ")[0-9a-f]{24}("(,?))$', re.M), r"\g<1><TOKEN>\g<2>"),
    ("regions-wall", re.compile(r"( monodromy evaluations in )" + NUM + r"( s)$", re.M), r"\g<1>" + WALL + r"\g<2>"),
    ("band-wall", re.compile(r"(\(\d+ evaluations, )" + NUM + r"( s\))"), r"\g<1>" + WALL + r"\g<2>"),
    (
        "chart-timing",
        re.compile(r"^(timing: \d+ points in )" + NUM + r"( s wall \()" + NUM + r"( us/point/thread, )", re.M),
        r"\g<1>" + WALL + r"\g<2>" + WALL + r"\g<3>",
    ),
    (
        "design-wall",
        re.compile(r"(Floquet evaluations, )" + NUM + r"( s optimising; verification \d+ evaluations, )" + NUM + r"( s;)"),
        r"\g<1>" + WALL + r"\g<2>" + WALL + r"\g<3>",
    ),
    (
        "report-cost",
        re.compile(r"^(- cost: |<li>cost: )(\d+ candidate designs, [^\n]*?, )" + NUM + r"( s)(?: \+ " + NUM + r" s)?", re.M),
        r"\g<1>\g<2>" + WALL + r"\g<3>",
    ),
    ("study-wall", re.compile(r"^(study: \d+ cases \([^)]*\) in )" + NUM + r"( s;)", re.M), r"\g<1>" + WALL + r"\g<2>"),
    ("progress-line", re.compile(r"^progress: [^\n]*\n", re.M), ""),
]


def seconds_column_csv(text):
    """Replace the cells of a CSV column headed `seconds`; returns (text, cells replaced).

    The file is rewritten only when Python's writer reproduces it byte for byte with
    nothing replaced, so quoting is never what makes two files equal; otherwise the file
    is compared as it is.
    """
    rows = list(csv.reader(io.StringIO(text, newline="")))
    if not rows or "seconds" not in rows[0]:
        return text, 0

    def write(rows):
        out = io.StringIO(newline="")
        csv.writer(out, lineterminator="\n").writerows(rows)
        return out.getvalue()

    if write(rows) != text:
        return text, 0
    col = rows[0].index("seconds")
    n = 0
    for row in rows[1:]:
        if len(row) > col:
            row[col] = WALL
            n += 1
    return write(rows), n


CELL = re.compile(r"(?<!\\)\|")


def seconds_column_md(text):
    """Replace the cells under a Markdown table header cell `seconds` (cells split at
    unescaped `|`)."""
    out, col, n = [], None, 0
    for line in text.split("\n"):
        cells = CELL.split(line)
        if line.startswith("|") and col is None:
            names = [c.strip() for c in cells]
            col = names.index("seconds") if "seconds" in names else -1
        elif not line.startswith("|"):
            col = None
        elif col is not None and col >= 0 and len(cells) > col and not set(cells[col].strip()) <= set("-:"):
            cells[col] = " " + WALL + " "
            line = "|".join(cells)  # the separators split on were all plain `|`
            n += 1
        out.append(line)
    return "\n".join(out), n


OWNED = re.compile(r'^(\s*"([^"/\\]+)": ")([0-9a-f]{64})(",?)$', re.M)


def owned_hashes(path, text):
    """Replace the hashes in `.rotorshunt-out.json` that are the sha256 of the named file
    beside it; returns (text, hashes replaced)."""
    n = 0

    def repl(m):
        nonlocal n
        f = path.parent / m.group(2)
        if f.is_file() and hashlib.sha256(f.read_bytes()).hexdigest() == m.group(3):
            n += 1
            return f"{m.group(1)}<SHA256 OF {m.group(2)}>{m.group(4)}"
        return m.group(0)

    return OWNED.sub(repl, text), n


def normalise(path, text, counts):
    n = 0
    if path.name == ".rotorshunt-out.json":
        text, n = owned_hashes(path, text)
    counts["owned-hash"] = counts.get("owned-hash", 0) + n
    for name, pattern, repl in RULES:
        text, n = pattern.subn(repl, text)
        counts[name] = counts.get(name, 0) + n
    n = 0
    if path.suffix == ".csv":
        text, n = seconds_column_csv(text)
    elif path.suffix == ".md":
        text, n = seconds_column_md(text)
    counts["table-seconds"] = counts.get("table-seconds", 0) + n
    return text


def files(root):
    return {p.relative_to(root).as_posix() for p in root.rglob("*") if p.is_file()}


def first_differences(a, b, limit=3):
    """The first `limit` differing lines as printable text."""
    la, lb = a.split("\n"), b.split("\n")
    shown = []
    for i in range(max(len(la), len(lb))):
        x = la[i] if i < len(la) else "<no line>"
        y = lb[i] if i < len(lb) else "<no line>"
        if x != y:
            shown.append(f"    line {i + 1}:\n      base: {x[:240]}\n      head: {y[:240]}")
            if len(shown) == limit:
                break
    if len(la) != len(lb):
        shown.append(f"    (base {len(la)} lines, head {len(lb)} lines)")
    return "\n".join(shown)


def main():
    if len(sys.argv) != 3:
        print("usage: compare.py BASE_DIR HEAD_DIR", file=sys.stderr)
        return 2
    base, head = Path(sys.argv[1]), Path(sys.argv[2])
    names = sorted(files(base) | files(head))
    counts = {"base": {}, "head": {}}
    differ = 0
    for name in names:
        pa, pb = base / name, head / name
        if not pa.exists() or not pb.exists():
            differ += 1
            print(f"DIFFERS {name}: only in {'head' if pb.exists() else 'base'}")
            continue
        a, b = pa.read_bytes(), pb.read_bytes()
        if name.endswith(".png"):
            if a != b:
                differ += 1
                at = next((i for i, (x, y) in enumerate(zip(a, b)) if x != y), min(len(a), len(b)))
                print(f"DIFFERS {name}: PNG bytes differ from byte {at} (base {len(a)} bytes, head {len(b)})")
            continue
        ta = normalise(pa, a.decode("utf-8", "backslashreplace"), counts["base"])
        tb = normalise(pb, b.decode("utf-8", "backslashreplace"), counts["head"])
        if ta != tb:
            differ += 1
            print(f"DIFFERS {name}:\n{first_differences(ta, tb)}")
    rules = ["owned-hash"] + [name for name, _, _ in RULES] + ["table-seconds"]
    print("normalised (replacements base/head): " + ", ".join(
        f"{r} {counts['base'].get(r, 0)}/{counts['head'].get(r, 0)}" for r in rules))
    print(f"{len(names)} files compared, {differ} differ")
    return 1 if differ else 0


if __name__ == "__main__":
    sys.exit(main())
