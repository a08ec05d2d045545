#!/usr/bin/env python3
"""Rewrites the figures of the documentation's command-line examples after a change that moves
them (README.md and docs/cli.md, the blocks tests/service/test_readme_cli.cpp runs).

Usage: scripts/refresh-doc-figures.py [--check] [FILE ...]   (from the repository root, after a
build; default files README.md docs/cli.md)

Each example is run as the test runs it (`build/rollgap run ARGS`, the echoed request on stdin).
A CSV block's lines are replaced by the printed lines (as many as the block shows). In a JSON
block every number the block shows is replaced by the printed number nearest to it (relative
difference below 1e-3, the same sign), spelled as the program spells it; a shown number with no
such partner is reported and left alone, so a figure that moved by more than a rounding is seen by
a person (and by the test) rather than rewritten. "Nearest under the same key" can pick the wrong
number where one key repeats with close values (an amplitude and its windows' amplitudes): the
test names the pointer, which is then corrected by hand. Prints a line per changed figure; --check
changes nothing and exits 1 if anything would change. The test stays the judge: run it after.
"""

import re
import subprocess
import sys

NUMBER = re.compile(r'(?<![\w."])-?\d+(?:\.\d+)?(?:[eE][-+]?\d+)?(?![\w"])')


KEY = re.compile(r'"(\w+)"\s*:\s*$')


def key_before(text, at):
    """The JSON key a number at `at` stands under, or None (an array element, a CSV cell)."""
    m = KEY.search(text[max(0, at - 80):at])
    return m.group(1) if m else None


def blocks(lines):
    start = None
    for i, line in enumerate(lines):
        if line.strip().startswith("```"):
            if start is None:
                start = i
            else:
                yield start, i
                start = None


def command_of(body):
    command, last = body[0].strip(), 0
    while command.endswith("\\") and last + 1 < len(body):
        last += 1
        command = command[:-1] + " " + body[last].strip()
    stdin = None
    rest = command
    if rest.startswith("echo '"):
        end = rest.index("'", 6)
        stdin, rest = rest[6:end], rest[end + 1:].strip()
        if not rest.startswith("|"):
            return None
        rest = rest[1:].strip()
    if not rest.startswith("build/rollgap run "):
        return None
    return rest.split(), stdin, last


def refresh(path, check):
    with open(path, encoding="utf-8") as f:
        lines = f.read().split("\n")
    changed = 0
    for open_at, close_at in list(blocks(lines)):
        body = lines[open_at + 1:close_at]
        found = command_of(body) if body else None
        if not found:
            continue
        argv, stdin, last = found
        run = subprocess.run(argv, input=stdin, capture_output=True, text=True, check=False)
        printed = run.stdout
        shown_from = open_at + 1 + last + 1
        if "--format" in argv and "csv" in argv:
            out = printed.replace("\r\n", "\n").split("\n")
            for k in range(shown_from, close_at):
                new = out[k - shown_from] if k - shown_from < len(out) else lines[k]
                if new != lines[k]:
                    print(f"{path}:{k + 1}: {lines[k]!r} -> {new!r}")
                    lines[k] = new
                    changed += 1
            continue
        # each printed number with the key it stands under ("key": number), if any
        tokens = [(m.group(0), float(m.group(0)), key_before(printed, m.start()))
                  for m in NUMBER.finditer(printed)]
        for k in range(shown_from, close_at):
            def nearest(match):
                nonlocal changed
                literal = match.group(0)
                value = float(literal)
                key = key_before(match.string, match.start())
                best = None
                for text, v, printed_key in tokens:
                    if (v < 0) != (value < 0) or (key and printed_key != key):
                        continue
                    d = abs(v - value) / max(abs(value), 1e-300)
                    if d < 1e-3 and (best is None or d < best[0]):
                        best = (d, text)
                if best is None:
                    print(f"{path}:{k + 1}: no printed figure near {literal}", file=sys.stderr)
                    return literal
                # keep the shown precision: a rounded figure stays rounded
                text = best[1]
                if "." in literal and len(literal.split(".")[1]) < 12 and "e" not in literal.lower():
                    digits = len(literal.split(".")[1])
                    text = f"{float(text):.{digits}f}"
                elif "." not in literal and "e" not in literal.lower() and "." in text:
                    text = literal if abs(float(text) - value) < 0.5 else str(round(float(text)))
                if text != literal:
                    changed += 1
                return text

            new = NUMBER.sub(nearest, lines[k])
            if new != lines[k]:
                print(f"{path}:{k + 1}: figures refreshed")
                lines[k] = new
    if changed and not check:
        with open(path, "w", encoding="utf-8") as f:
            f.write("\n".join(lines))
    return changed


def main():
    args = [a for a in sys.argv[1:] if a != "--check"]
    check = "--check" in sys.argv[1:]
    files = args or ["README.md", "docs/cli.md"]
    total = sum(refresh(p, check) for p in files)
    print(f"{total} figure(s) {'would change' if check else 'changed'}")
    return 1 if check and total else 0


if __name__ == "__main__":
    sys.exit(main())
