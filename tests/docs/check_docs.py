#!/usr/bin/env python3
"""The documentation holds together: its links resolve, every deck key is documented, the README's
deck runs, and the guides carry no history.

Usage: check_docs.py --run EPAPHE_RUN --source DIR --workdir DIR

Checked, over README.md and docs/**/*.md (the source tree's):
  - links: every relative link or image, [text](target) outside code, names a file or directory that
    exists (relative to the page), and its #anchor, if any, a heading of the target page (GitHub's
    anchors: lower case, punctuation dropped, spaces as hyphens, -1, -2 ... for repeats); a bare
    #anchor names a heading of the page itself. Links to other sites are not fetched.
  - deck keys: `epaphe-run --print-parameters` prints every list ("[Name]  doc", indented two
    spaces per level; "[<any name>]" a list named by the user) and every key ("Key (type, default
    ...)", its documentation on the next line). Each key must appear, in backticks, in the section
    of docs/user/parameters.md whose heading names its list's path in backticks (`Output`,
    `Bodies-><name>->Mesh`): a key the schema gains fails here until the user guide documents it,
    and a key dropped from the page fails too.
  - the README's deck: each ```xml block of README.md that is a whole deck (<ParameterList
    name="Epaphe">) passes `epaphe-run --check`.
  - no history in README.md, docs/user, docs/theory, docs/developer: no date (YYYY-MM-DD) and no
    commit hash (7 to 40 hexadecimal digits with at least one digit and one letter), outside code
    blocks and inside them alike.
  - floors: each packages/*/CMakeLists.txt says "Floor N" once, N its longest path of USES from core
    (core is floor 0; docs/developer/architecture.md, "The package graph").
"""
import argparse
import glob
import os
import re
import subprocess
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "verification"))
from epaphe_testing import verdict  # noqa: E402

RUN_TIMEOUT = 120  # --print-parameters and --check take well under a second
FENCE = re.compile(r"^\s*(```|~~~)")
LINK = re.compile(r"!?\[(?:[^\[\]]|\[[^\]]*\])*\]\(\s*<?([^)\s>]+)>?(?:\s+\"[^\"]*\")?\s*\)")
CODE_SPAN = re.compile(r"`+[^`]*`+")
HEADING = re.compile(r"^(#{1,6})\s+(.*?)\s*#*\s*$")
DATE = re.compile(r"\b(?:19|20)\d\d-[01]\d-[0-3]\d\b")
HASH = re.compile(r"\b(?=[0-9a-f]*[0-9])(?=[0-9a-f]*[a-f])[0-9a-f]{7,40}\b")
NO_HISTORY = ("README.md", "docs/user", "docs/theory", "docs/developer")


def pages(source):
    return [os.path.join(source, "README.md")] + sorted(
        glob.glob(os.path.join(source, "docs", "**", "*.md"), recursive=True)
    )


def prose_lines(text):
    """(line number, line) outside fenced code blocks."""
    inside = False
    for n, line in enumerate(text.splitlines(), 1):
        if FENCE.match(line):
            inside = not inside
            continue
        if not inside:
            yield n, line


def slug(heading):
    """GitHub's anchor of a heading's text."""
    text = re.sub(r"!?\[([^\]]*)\]\([^)]*\)", r"\1", heading)  # a link's text only
    text = text.replace("`", "").strip().lower()
    text = re.sub(r"[^\w\- ]", "", text)
    return text.replace(" ", "-")


def anchors(path, cache={}):  # noqa: B006 (a cache on purpose)
    if path not in cache:
        seen, out = {}, set()
        with open(path, encoding="utf-8") as fh:
            for _, line in prose_lines(fh.read()):
                m = HEADING.match(line)
                if not m:
                    continue
                s = slug(m.group(2))
                k = seen.get(s, 0)
                seen[s] = k + 1
                out.add(s if k == 0 else f"{s}-{k}")
        cache[path] = out
    return cache[path]


def check_links(source, failures):
    count = 0
    for page in pages(source):
        rel_page = os.path.relpath(page, source)
        with open(page, encoding="utf-8") as fh:
            text = fh.read()
        for n, line in prose_lines(text):
            for m in LINK.finditer(CODE_SPAN.sub("", line)):
                target = m.group(1)
                if re.match(r"^[a-z][a-z0-9+.-]*:", target, re.I):  # http:, https:, mailto:
                    continue
                count += 1
                path, _, anchor = target.partition("#")
                dest = os.path.normpath(os.path.join(os.path.dirname(page), path)) if path else page
                where = f"{rel_page}:{n}: link '{target}'"
                if not os.path.exists(dest):
                    failures.append(f"{where}: no {os.path.relpath(dest, source)}; fix the path (relative to the page)")
                    continue
                if anchor and dest.endswith(".md") and anchor not in anchors(dest):
                    failures.append(
                        f"{where}: {os.path.relpath(dest, source)} has no heading with anchor #{anchor} "
                        f"(its anchors: {', '.join(sorted(anchors(dest)))})"
                    )
    print(f"links: {count} relative links in {len(pages(source))} pages checked")
    return count


def printed_keys(run):
    """[(list path, key)] from `epaphe-run --print-parameters`."""
    proc = subprocess.run([run, "--print-parameters"], capture_output=True, text=True, timeout=RUN_TIMEOUT)
    if proc.returncode != 0:
        raise SystemExit(f"epaphe-run --print-parameters failed ({proc.returncode}):\n{proc.stdout}\n{proc.stderr}")
    lines = proc.stdout.splitlines()
    if not lines or not lines[0].startswith("Epaphe "):
        raise SystemExit(f"--print-parameters: its first line is not the title 'Epaphe <version>: ...': {lines[:1]}")
    stack, keys, i = [], [], 1
    while i < len(lines):
        line = lines[i]
        i += 1
        if not line.strip():
            continue
        indent = len(line) - len(line.lstrip(" "))
        if indent % 2:
            raise SystemExit(f"--print-parameters line {i}: indentation {indent} is not a multiple of 2: {line!r}")
        del stack[indent // 2 :]
        body = line.strip()
        m = re.match(r"^\[(.+?)\](?:\s{2}.*)?$", body)
        if m:
            stack.append("<name>" if m.group(1) == "<any name>" else m.group(1))
            continue
        m = re.match(r"^(.+?) \((.+?), default ", body)
        if not m:
            raise SystemExit(f"--print-parameters line {i}: neither a list nor a key: {line!r}")
        keys.append(("->".join(stack), m.group(1)))
        i += 1  # its documentation line
    return keys


def parameter_sections(path):
    """{list path: (set of `backticked` words, [(line, key) of the table rows])} of
    docs/user/parameters.md's sections; a row's key is the backticked word of its first cell."""
    sections, current = {}, None
    with open(path, encoding="utf-8") as fh:
        text = fh.read()
    inside = False
    for n, line in enumerate(text.splitlines(), 1):
        if FENCE.match(line):
            inside = not inside
            continue
        m = HEADING.match(line) if not inside else None
        if m:
            names = re.findall(r"`([^`]+)`", m.group(2))
            current = names[0] if names else None
            if current is not None:
                sections.setdefault(current, (set(), []))
            continue
        if current is None:
            continue
        sections[current][0].update(re.findall(r"`([^`]+)`", line))
        row = re.match(r"^\|\s*`([^`]+)`\s*\|", line)
        if row:
            sections[current][1].append((n, row.group(1)))
    return sections


def check_keys(run, source, failures):
    keys = printed_keys(run)
    page = os.path.join(source, "docs", "user", "parameters.md")
    sections = parameter_sections(page)
    missing_lists = sorted({lst for lst, _ in keys if lst not in sections})
    for lst in missing_lists:
        failures.append(
            f"docs/user/parameters.md: no section for the list `{lst}` (a heading with `{lst}` in "
            f"backticks) though --print-parameters prints its keys"
        )
    for lst, key in keys:
        if lst in sections and key not in sections[lst][0]:
            failures.append(
                f"docs/user/parameters.md, section `{lst}`: the deck key `{key}` (printed by "
                f"--print-parameters) is not documented; add a row with `{key}` in backticks"
            )
    printed = set(keys)
    for lst, (_, rows) in sections.items():
        for n, key in rows:
            if (lst, key) not in printed:
                failures.append(
                    f"docs/user/parameters.md:{n}: `{key}` in section `{lst}` is no deck key "
                    f"(--print-parameters has none of that name in that list); remove or fix the row"
                )
    print(
        f"deck keys: {len(keys)} keys in {len({lst for lst, _ in keys})} lists checked against "
        f"docs/user/parameters.md"
    )
    return len(keys)


def check_readme_deck(run, source, workdir, failures):
    with open(os.path.join(source, "README.md"), encoding="utf-8") as fh:
        blocks = re.findall(r"```xml\n(.*?)```", fh.read(), re.S)
    decks = [b for b in blocks if b.lstrip().startswith('<ParameterList name="Epaphe">')]
    if not decks:
        failures.append('README.md: no ```xml block holding a whole deck (<ParameterList name="Epaphe">)')
    for k, deck in enumerate(decks):
        path = os.path.join(workdir, f"readme-deck-{k}.xml")
        with open(path, "w", encoding="utf-8") as fh:
            fh.write(deck)
        proc = subprocess.run([run, path, "--check"], cwd=workdir, capture_output=True, text=True, timeout=RUN_TIMEOUT)
        print(f"README deck {k}: epaphe-run --check exit {proc.returncode}")
        if proc.returncode != 0:
            failures.append(
                f"README.md: its deck (xml block {k}) fails epaphe-run --check: "
                f"{(proc.stderr or proc.stdout).strip()[-500:]}"
            )


def check_no_history(source, failures):
    files = [
        p
        for p in pages(source)
        if any(os.path.relpath(p, source) == d or os.path.relpath(p, source).startswith(d + os.sep) for d in NO_HISTORY)
    ]
    for path in files:
        with open(path, encoding="utf-8") as fh:
            for n, line in enumerate(fh, 1):
                for pattern, what in ((DATE, "a date"), (HASH, "a commit hash")):
                    for m in pattern.finditer(line):
                        failures.append(
                            f"{os.path.relpath(path, source)}:{n}: {what} '{m.group(0)}': the user, "
                            f"theory and developer guides and the README hold no history "
                            f"(it belongs in CHANGELOG.md)"
                        )
    print(f"history: {len(files)} pages checked for dates and commit hashes")


def check_floors(source, failures):
    uses, said = {}, {}
    for path in sorted(glob.glob(os.path.join(source, "packages", "*", "CMakeLists.txt"))):
        with open(path, encoding="utf-8") as fh:
            text = fh.read()
        name = os.path.basename(os.path.dirname(path))
        m = re.search(r"^\s*USES\s+([^\n]*)", text, re.M)
        uses[name] = [u for u in (m.group(1).split() if m else []) if u != name]
        floors = re.findall(r"Floor (\d+)", text)
        if len(floors) != 1:
            failures.append(f"packages/{name}/CMakeLists.txt: {len(floors)} 'Floor N' labels, expected one")
        else:
            said[name] = int(floors[0])

    def floor(name, seen=()):
        if name in seen:
            raise ValueError(f"a cycle in USES: {' -> '.join(seen + (name,))}")
        return max((1 + floor(u, seen + (name,)) for u in uses.get(name, [])), default=0)

    for name, n in said.items():
        want = floor(name)
        if n != want:
            failures.append(
                f"packages/{name}/CMakeLists.txt: says Floor {n}, but its longest path of USES from "
                f"core is {want}: write Floor {want}"
            )
    print(f"floors: {len(said)} packages checked against their USES")
    return len(said)


def main():
    ap = argparse.ArgumentParser()
    for name in ("--run", "--source", "--workdir"):
        ap.add_argument(name, required=True)
    a = ap.parse_args()
    a.run, a.source = os.path.abspath(a.run), os.path.abspath(a.source)
    os.makedirs(a.workdir, exist_ok=True)
    failures = []
    if check_links(a.source, failures) == 0:
        failures.append("no relative link found at all: the link pattern is broken")
    if check_keys(a.run, a.source, failures) == 0:
        failures.append("no deck key read from --print-parameters: its parsing is broken")
    check_readme_deck(a.run, a.source, a.workdir, failures)
    check_no_history(a.source, failures)
    if check_floors(a.source, failures) == 0:
        failures.append("no package's floor read: the packages/*/CMakeLists.txt pattern is broken")
    return verdict(failures)


if __name__ == "__main__":
    sys.exit(main())
