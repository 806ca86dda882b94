#!/usr/bin/env python3
"""The library's public API as a list, read off rustdoc's HTML, and its check.

    scripts/public-api.py [--check | --write] [DOC_DIR]

Reads the crate's documentation (DOC_DIR, default target/doc/rotorshunt, written by
`cargo doc --no-deps`) and lists every public item by its path: modules, structs, enums,
traits, functions, constants, statics, type aliases and macros (rustdoc's all.html), and
of each struct, enum, union and trait its public fields, variants, inherent methods,
associated constants and types and required methods (the anchors of its page; trait
implementations are left out, their methods being the trait's). One line per item,
`kind path`, sorted.

--check (the default) compares the list with docs/public-api.txt and exits 1 printing
the items added and removed, so that a change of the public API is a change of that file,
seen in review and in CHANGELOG.md; --write rewrites the file. Exit 2 when the docs are
missing. Signatures are not compared: a changed argument list is caught by the compiler
in the tests and examples that call it, and named in CHANGELOG.md.
"""

import html
import pathlib
import re
import sys

ROOT = pathlib.Path(__file__).resolve().parent.parent
LIST = ROOT / "docs" / "public-api.txt"

# The sections of all.html and the kind each lists.
SECTIONS = {
    "modules": "mod",
    "structs": "struct",
    "enums": "enum",
    "unions": "union",
    "traits": "trait",
    "functions": "fn",
    "constants": "const",
    "statics": "static",
    "types": "type",
    "macros": "macro",
    "derives": "derive",
    "attributes": "attr",
    "trait-aliases": "traitalias",
}
# Anchors of a type's page that name its own members, and the kind each is.
MEMBERS = {
    "structfield": "field",
    "variant": "variant",
    "method": "method",
    "associatedconstant": "assoc-const",
    "associatedtype": "assoc-type",
    "tymethod": "required-method",
}


def items(doc: pathlib.Path):
    """Every (kind, path) rustdoc lists in all.html, and the pages of types and traits."""
    text = (doc / "all.html").read_text(encoding="utf-8")
    kind = None
    out, pages = [], []
    for m in re.finditer(r'<h3 id="([a-z-]+)">|<li><a href="([^"]+)">([^<]+)</a></li>', text):
        if m.group(1):
            kind = SECTIONS.get(m.group(1), m.group(1))
            continue
        path = "rotorshunt::" + html.unescape(m.group(3))
        out.append((kind, path))
        if kind in ("struct", "enum", "union", "trait"):
            pages.append((path, doc / m.group(2)))
    return out, pages


def own_part(page: str) -> str:
    """The part of a type's page with its own members: everything before the trait
    implementations (rustdoc's `trait-implementations` heading), which hold the members of
    the traits it implements."""
    cut = [page.find(marker) for marker in ('id="trait-implementations"', 'id="synthetic-implementations"',
                                            'id="blanket-implementations"', 'id="implementors"')]
    cut = [c for c in cut if c >= 0]
    return page[: min(cut)] if cut else page


def members(path: str, page_file: pathlib.Path):
    """The own members of the type or trait at `path`, from its page."""
    page = own_part(page_file.read_text(encoding="utf-8"))
    found = set()
    for m in re.finditer(r'id="(structfield|variant|method|associatedconstant|associatedtype|tymethod)\.([A-Za-z0-9_]+)"', page):
        found.add((MEMBERS[m.group(1)], f"{path}::{m.group(2)}"))
    # A variant's named fields: id="variant.Name.field.x".
    for m in re.finditer(r'id="variant\.([A-Za-z0-9_]+)\.field\.([A-Za-z0-9_]+)"', page):
        found.add(("variant-field", f"{path}::{m.group(1)}::{m.group(2)}"))
    return found


def api(doc: pathlib.Path):
    listed, pages = items(doc)
    everything = set(listed)
    for path, page in pages:
        everything |= members(path, page)
    return sorted(f"{kind} {path}" for kind, path in everything)


def main(argv):
    mode = "--check"
    args = [a for a in argv if not a.startswith("--")]
    for a in argv:
        if a in ("--check", "--write"):
            mode = a
        elif a.startswith("--"):
            print(f"unknown option {a}; usage: scripts/public-api.py [--check | --write] [DOC_DIR]", file=sys.stderr)
            return 2
    doc = pathlib.Path(args[0]) if args else ROOT / "target" / "doc" / "rotorshunt"
    if not (doc / "all.html").is_file():
        print(f"no documentation at {doc}: run `cargo doc --release --no-deps` first", file=sys.stderr)
        return 2
    lines = api(doc)
    if any(line.split(" ", 1)[1].startswith("rotorshunt::commands::") for line in lines):
        print(f"{doc} holds the binary's documentation (its private command layer), not the library's: "
              "run `cargo doc --release --no-deps` after the binary's", file=sys.stderr)
        return 2
    if mode == "--write":
        LIST.write_text("".join(line + "\n" for line in lines), encoding="utf-8")
        print(f"{len(lines)} public items written to {LIST.relative_to(ROOT)}")
        return 0
    kept = LIST.read_text(encoding="utf-8").splitlines() if LIST.is_file() else []
    added = sorted(set(lines) - set(kept))
    removed = sorted(set(kept) - set(lines))
    if not added and not removed:
        print(f"public API: {len(lines)} items, as listed in {LIST.relative_to(ROOT)}")
        return 0
    print(f"the public API differs from {LIST.relative_to(ROOT)} ({len(added)} added, {len(removed)} removed):")
    for line in added:
        print(f"  + {line}")
    for line in removed:
        print(f"  - {line}")
    print("If the change is meant, run scripts/public-api.py --write and say so in CHANGELOG.md.")
    return 1


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
