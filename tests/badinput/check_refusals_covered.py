#!/usr/bin/env python3
"""Every refusal in packages/ is exercised by a test, or listed with the reason it is not.

A refusal site is an `EPAPHE_REQUIRE(condition, message)`, a `throw Error(...)` /
`throw epaphe::Error(...)`, an `ErrorBuilder eb; eb << ...; eb.raise();`, or a call of a
`[[noreturn]]` function of the same file (Hdf5File's `fail(file, message)`), in packages/*/src. A
`std::ostringstream os` thrown as `Error(os.str())` takes the text of its `os << ...` lines. Its message
is read from the source: the string literals streamed or concatenated into it, in order (a literal
passed to a call inside the message, such as a key given to deck::pathOf, is not its text; nor is
"xyz"[d]). Literals with nothing printed between them are one fragment; what is computed at run time
falls between fragments.

Matching is by runs of 2 to MAX_TOKENS tokens (words, or runs of punctuation) inside one fragment. A
run tells a site when no other site's message holds it, and it is more than a deck key or a path of
keys (a message prints those from the deck: 'Time->End revolutions'). Sites with equal fragments are
twins: a user cannot tell them apart, so they are exercised together. A run that only sites listed as
out of a deck's reach share with a site still tells that site in what a deck run prints. A site is
exercised when a run that tells it is in

  - the expected message of a tests/badinput/cases deck (its `<!-- expect: REGEX -->`, regex escapes
    removed), which badinput.catalogue checks the run prints, or of a deck check_bad_decks.py makes;
  - a string another test asserts is in a message (C++ `.find("...")`, Python `"..." in err`,
    `re.search("...", err)`, an expect.txt line of a package's test fixtures): runs of CASE_WORDS
    words or more;
  - another string of a test (prose about a refusal, a deck): runs of TEST_WORDS words or more.

refusals-allow-list.txt lists the others, each with its reason (its header gives the three kinds:
out of a deck's reach, exercised by a named case or test whose text cannot tell it, a known gap).
The check fails when a site is neither exercised nor listed, when an entry names no site (or several
that are not twins), when a listed site is exercised after all (the list stays exact), or when a
case or test an entry names does not exist. It reads sources only, and runs in seconds.
--report prints every site with what exercises it or why it is listed.
"""
import argparse
import ast
import glob
import os
import re
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.normpath(os.path.join(HERE, "..", ".."))
ALLOW = os.path.join(HERE, "refusals-allow-list.txt")
# A run of 2 to MAX_TOKENS tokens (words or punctuation) found in one message only tells its site: in
# a case's expected message, or a string another test asserts is in a message, a run of CASE_WORDS
# words or more; in another test's other strings, which may be prose about a refusal, TEST_WORDS.
MAX_TOKENS, CASE_WORDS, TEST_WORDS = 8, 2, 4


# ---- C++ source: comments blanked, string literals located ----------------------------------------
def scan_cpp(text):
    """(text with comments blanked, [(start, end, value)] of its string literals)."""
    out = list(text)
    lits = []
    i, n = 0, len(text)
    while i < n:
        c = text[i]
        if text.startswith("//", i):
            j = text.find("\n", i)
            j = n if j < 0 else j
            out[i:j] = " " * (j - i)
            i = j
        elif text.startswith("/*", i):
            j = text.find("*/", i + 2)
            j = n if j < 0 else j + 2
            out[i:j] = [ch if ch == "\n" else " " for ch in text[i:j]]
            i = j
        elif c == '"' and text[max(0, i - 1)] == "R":
            m = re.compile(r'"([^(\s]*)\(').match(text, i)
            end = text.index(")" + m.group(1) + '"', m.end())
            lits.append((i, end + len(m.group(1)) + 2, text[m.end() : end]))
            i = end + len(m.group(1)) + 2
        elif c == '"':
            j, val = i + 1, []
            while text[j] != '"':
                if text[j] == "\\":
                    val.append({"n": "\n", "t": "\t"}.get(text[j + 1], text[j + 1]))
                    j += 2
                else:
                    val.append(text[j])
                    j += 1
            lits.append((i, j + 1, "".join(val)))
            i = j + 1
        elif c == "'" and not text[max(0, i - 1)].isalnum():  # a char literal, not a digit separator
            j = i + 1
            while text[j] != "'":
                j += 2 if text[j] == "\\" else 1
            i = j + 1
        else:
            i += 1
    return "".join(out), lits


def skip_to_close(clean, lits, i):
    """Index of the bracket closing the one at i."""
    ends = {s: e for s, e, _ in lits}
    depth = 0
    while True:
        if i in ends:
            i = ends[i]
            continue
        if clean[i] in "([{":
            depth += 1
        elif clean[i] in ")]}":
            depth -= 1
            if depth == 0:
                return i
        i += 1


def first_top_comma(clean, lits, i, end):
    ends = {s: e for s, e, _ in lits}
    depth = 0
    while i < end:
        if i in ends:
            i = ends[i]
            continue
        if clean[i] in "([{":
            depth += 1
        elif clean[i] in ")]}":
            depth -= 1
        elif clean[i] == "," and depth == 0:
            return i
        i += 1
    raise ValueError("EPAPHE_REQUIRE without a message")


def statement_end(clean, lits, i):
    """Index of the ';' ending the statement at i (a ';' inside a string literal does not)."""
    ends = {s: e for s, e, _ in lits}
    while clean[i] != ";":
        i = ends.get(i, i + 1)
    return i


def message_fragments(clean, lits, a, b):
    """The literals printed by the message text clean[a:b], adjacent ones joined."""
    # the brackets open at each literal: a literal inside a call's parentheses is an argument, not text
    opened, frags, last = [], [], None
    ends = {s: (e, v) for s, e, v in lits}
    i = a
    while i < b:
        if i in ends:
            e, v = ends[i]
            if re.match(r"\s*\[", clean[e:b]):  # "xyz"[d]: one character of it, computed
                last = None
            elif all(is_group for is_group in opened):
                between = clean[last:i] if last is not None else None
                if between is not None and re.fullmatch(r"[\s<+]*", between) and frags:
                    frags[-1] += v
                else:
                    frags.append(v)
                last = e
            i = e
            continue
        ch = clean[i]
        if ch == "(":  # grouping unless it calls: follows a name, a template's '>' or a subscript
            before = clean[a:i].rstrip()
            opened.append(not re.search(r"[\w>\]]$", before) or before.endswith("std::string"))
        elif ch in "[{":
            opened.append(False)
        elif ch in ")]}" and opened:
            opened.pop()
        i += 1
    return frags


def noreturn_helpers(path):
    """Names of the [[noreturn]] functions declared in a source file or its header: their calls raise."""
    names = set()
    for p in {path, os.path.splitext(path)[0] + ".hpp", os.path.splitext(path)[0] + ".cpp"}:
        if os.path.exists(p):
            names.update(
                re.findall(
                    r"\[\[noreturn\]\]\s+(?:static\s+)?void\s+(?:\w+::)?(\w+)\s*\(",
                    scan_cpp(open(p, encoding="utf-8").read())[0],
                )
            )
    return names


def sites_in(path):
    """[(line, fragments)] of the refusal sites of one C++ file."""
    text = open(path, encoding="utf-8").read()
    clean, lits = scan_cpp(text)
    line = lambda i: text.count("\n", 0, i) + 1  # noqa: E731
    found = []
    for m in re.finditer(r"\bEPAPHE_REQUIRE\s*\(", clean):
        if re.search(r"#\s*define\s+$", clean[: m.start()]):
            continue
        end = skip_to_close(clean, lits, m.end() - 1)
        comma = first_top_comma(clean, lits, m.end(), end)
        found.append((line(m.start()), message_fragments(clean, lits, comma + 1, end)))
    for m in re.finditer(r"\bthrow\s+(?:(?:::)?epaphe::)?Error\s*\(", clean):
        end = skip_to_close(clean, lits, m.end() - 1)
        frags = message_fragments(clean, lits, m.end(), end)
        stream = re.match(r"\s*(\w+)\.str\(\)", clean[m.end() : end])
        if stream:  # std::ostringstream os; os << ...; throw Error(os.str() ...)
            decl = clean.rfind("std::ostringstream " + stream.group(1), 0, m.start())
            if decl >= 0:
                frags = [
                    f
                    for s in re.finditer(r"\b%s\s*<<" % stream.group(1), clean[decl : m.start()])
                    for f in message_fragments(
                        clean, lits, decl + s.start(), statement_end(clean, lits, decl + s.end())
                    )
                ] + frags
        found.append((line(m.start()), frags))
    for m in re.finditer(r"\bErrorBuilder\s+(\w+)\s*;", clean):
        raise_at = clean.index(m.group(1) + ".raise()", m.end())
        frags = []
        for s in re.finditer(r"\b%s\s*<<" % m.group(1), clean[m.end() : raise_at]):
            start = m.end() + s.start()
            frags += message_fragments(clean, lits, start, statement_end(clean, lits, start))
        found.append((line(m.start()), frags))
    for name in noreturn_helpers(path):  # fail(file, "message"): every literal passed is its text
        for m in re.finditer(r"(?<![\w.>:])%s\s*\(" % name, clean):
            if re.search(r"\bvoid\s+(?:\w+::)?$", clean[: m.start()]):
                continue  # its declaration
            end = skip_to_close(clean, lits, m.end() - 1)
            found.append((line(m.start()), message_fragments(clean, lits, m.end(), end)))
    return sorted(found)


def all_sites():
    sites = []
    for path in sorted(glob.glob(os.path.join(ROOT, "packages", "*", "src", "*.[ch]pp"))):
        if os.path.basename(path) == "Epaphe_Error.hpp":  # the macro and the builder themselves
            continue
        rel = os.path.relpath(path, ROOT)
        sites += [dict(file=rel, line=ln, frags=fr) for ln, fr in sites_in(path)]
    return sites


# ---- what tests say ---------------------------------------------------------------------------------
def unescape(s):
    """A regex read as text: an escaped character stands for itself."""
    return re.sub(r"\\([^A-Za-z0-9])", r"\1", s)


def case_texts():
    """[(where, expected message, True)] of the badinput cases (those check_bad_decks.py makes too)."""
    out = []
    for path in sorted(glob.glob(os.path.join(HERE, "cases", "*.xml"))):
        m = re.match(r"<!-- expect: (.*) -->", open(path, encoding="utf-8").readline().strip())
        if m:
            out.append(("case " + os.path.basename(path), unescape(m.group(1)), True))
    sys.path.insert(0, HERE)
    from check_bad_decks import MADE_CASES  # the decks made in its work directory: missing, a directory, empty

    out += [("case " + name + " (made)", unescape(regex), True) for name, _, regex in MADE_CASES]
    return out


def python_strings(text):
    """[(string constant, asserted)] of a Python source, docstrings left out (prose, not a message);
    asserted: the pattern of a re call or the left side of an `in` test."""
    try:
        tree = ast.parse(text)
    except SyntaxError:
        return []
    docs = {id(n.value) for n in ast.walk(tree) if isinstance(n, ast.Expr) and isinstance(n.value, ast.Constant)}
    asserted = set()
    for n in ast.walk(tree):
        if isinstance(n, ast.Compare) and any(isinstance(op, (ast.In, ast.NotIn)) for op in n.ops):
            asserted.add(id(n.left))
        elif (
            isinstance(n, ast.Call)
            and isinstance(n.func, ast.Attribute)
            and n.args
            and n.func.attr in ("search", "match", "fullmatch")
        ):
            asserted.add(id(n.args[0]))
    return [
        (n.value, id(n) in asserted)
        for n in ast.walk(tree)
        if isinstance(n, ast.Constant) and isinstance(n.value, str) and id(n) not in docs
    ]


def cpp_strings(text):
    """[(string literal, asserted)] of a C++ test: asserted when searched for, `.find("...")`."""
    clean, lits = scan_cpp(text)
    return [(v, bool(re.search(r"\.find\(\s*$", clean[:s]))) for s, _, v in lits]


def test_texts():
    """[(where, string, asserted)] of the other tests: their sources' string literals, and the lines of
    the expect.txt files of package test fixtures (each a part of the message a fixture raises)."""
    own = {os.path.abspath(__file__), ALLOW}
    paths = [
        p
        for pattern in (
            "tests/**/*.py",
            "tests/**/*.cpp",
            "tests/**/*.hpp",
            "packages/*/test/**/*.cpp",
            "packages/*/test/**/*.hpp",
        )
        for p in glob.glob(os.path.join(ROOT, pattern), recursive=True)
        if os.path.abspath(p) not in own
    ]
    out = []
    for path in sorted(set(paths)):
        text = open(path, encoding="utf-8", errors="replace").read()
        strings = python_strings(text) if path.endswith(".py") else cpp_strings(text)
        out += [(os.path.relpath(path, ROOT), unescape(v), a) for v, a in strings if len(v) >= 8]
    for path in sorted(glob.glob(os.path.join(ROOT, "packages", "*", "test", "**", "expect.txt"), recursive=True)):
        where = os.path.relpath(os.path.dirname(path), ROOT)
        out += [
            (where, line.strip(), True)
            for line in open(path, encoding="utf-8")
            if line.strip() and not re.match(r"(format|missing): ", line)
        ]
    return out


# ---- matching -------------------------------------------------------------------------------------
TOKEN = re.compile(r"\w+|[^\w\s]+")  # a word, or a run of punctuation
WORD = re.compile(r"[A-Za-z]{2,}")


def key_names():
    """Deck key, list and enum names: capitalised literals passed to a call, listed or returned in
    packages/ (a message prints them as computed text, e.g. through deck::pathOf: they tell no site)."""
    names = set()
    for path in glob.glob(os.path.join(ROOT, "packages", "*", "src", "*.[ch]pp")):
        text = open(path, encoding="utf-8").read()
        names.update(re.findall(r'(?:[({,]|\breturn)\s*"([A-Z][\w ,\'()/+-]{0,40})"', text))
    return names


def windows(text, min_words):
    """Every run of 2 to MAX_TOKENS tokens of a text, as written, holding min_words words or more."""
    toks = list(TOKEN.finditer(text))
    out = set()
    for i in range(len(toks)):
        for j in range(i + 1, min(i + MAX_TOKENS, len(toks))):
            w = text[toks[i].start() : toks[j].end()]
            if len(WORD.findall(w)) >= min_words:
                out.add(w)
    return out


def classify(sites, unreachable):
    """Each site's windows (runs of tokens of its fragments), twins (equal fragments), and the windows
    that tell it: more than a deck key or a path of keys ('Time->Time step'), and in the message of no
    other site (telling), or of no other site a deck reaches (telling_deck: what a case may print), or
    of no other site at all, twins included (own)."""
    keys = key_names()

    def names_keys(w):
        words = re.search(r"\w.*\w", w)
        return not words or all(any(part in k for k in keys) for part in words.group(0).split("->"))

    owners = {}
    for s in sites:
        s["windows"] = {w for f in s["frags"] for w in windows(f, CASE_WORDS) if not names_keys(w)}
        for w in s["windows"]:
            owners.setdefault(w, set()).add(s["id"])
    for s in sites:
        s["twins"] = [t for t in sites if t is not s and t["key"] == s["key"]]
        s["telling"] = {w for w in s["windows"] if all(sites[o]["key"] == s["key"] for o in owners[w])}
        s["telling_deck"] = {
            w for w in s["windows"] if all(sites[o]["key"] == s["key"] for o in owners[w] if o not in unreachable)
        }
        s["own"] = {w for w in s["windows"] if owners[w] == {s["id"]}}


def read_allow_list(sites, failures):
    """The entries of the allow-list: [dict(line, sites, reason, by)]."""
    entries = []
    for n, raw in enumerate(open(ALLOW, encoding="utf-8"), 1):
        text = raw.strip()
        if not text or text.startswith("#"):
            continue
        parts = [p.strip() for p in text.split(" | ")]
        kind = "out"
        if len(parts) == 4 and parts[2].startswith("by "):
            kind, by = "by", parts[2][3:].strip()
        elif len(parts) == 4 and parts[2] == "gap":
            kind, by = "gap", None
        else:
            by = None
        if not (len(parts) == 3 or kind != "out") or not all(parts):
            failures.append(
                f"{os.path.basename(ALLOW)}:{n}: write FILE | FRAGMENT | REASON, "
                f"FILE | FRAGMENT | by WHERE | REASON or FILE | FRAGMENT | gap | REASON; got: {text}"
            )
            continue
        path, fragment, reason = parts[0], parts[1], parts[-1]
        regex = len(fragment) > 2 and fragment.startswith("/") and fragment.endswith("/")
        if regex:
            named = [s for s in sites if s["file"] == path and re.search(fragment[1:-1], skeleton(s))]
            ok = bool(named)
        else:
            named = [s for s in sites if s["file"] == path and any(fragment in f for f in s["frags"])]
            ok = len({s["key"] for s in named}) == 1
        if not ok:
            failures.append(
                f"{os.path.basename(ALLOW)}:{n}: '{fragment}' names {len(named)} refusal sites of {path} "
                f"({', '.join(str(s['line']) for s in named) or 'none'}); a fragment must name one site "
                f"(or its twins of the same message), a /regex/ at least one"
            )
            continue
        entries.append(dict(line=n, sites=named, reason=reason, by=by, kind=kind, regex=regex))
        for s in named:
            s.setdefault("entries", []).append(entries[-1])
    return entries


def words_of(text):
    return {w.lower() for w in re.findall(r"[A-Za-z]{2,}", text)}


def shown(site):
    return f"{site['file']}:{site['line']}"


def skeleton(site):
    return " ... ".join(site["frags"]) or "(no text of its own)"


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--report", action="store_true", help="print every site with what exercises it")
    a = ap.parse_args()
    failures = []
    sites = all_sites()
    for i, s in enumerate(sites):
        s["id"], s["key"] = i, tuple(s["frags"])
    entries = read_allow_list(sites, failures)
    texts = case_texts() + test_texts()
    # Each window of the tests' texts: where it is (a case: a deck run prints it).
    seen = {}
    for where, t, asserted in texts:
        for w in windows(t, CASE_WORDS if asserted else TEST_WORDS):
            seen.setdefault(w, set()).add(where)

    def assess():
        """Who exercises each site, given the sites listed as out of a deck's reach."""
        unreachable = {s["id"] for s in sites if any(e["kind"] == "out" for e in s.get("entries", []))}
        classify(sites, unreachable)
        for s in sites:
            found = {where for w in s["telling"] for where in seen.get(w, ())}
            found |= {where for w in s["telling_deck"] for where in seen.get(w, ()) if where.startswith("case ")}
            s["by"] = found
            s["by_own"] = {where for w in s["own"] if len(WORD.findall(w)) >= TEST_WORDS for where in seen.get(w, ())}
        for s in sites:  # twins a deck reaches are exercised together
            if s["id"] not in unreachable:
                s["by"] = s["by"] | {w for t in s["twins"] if t["id"] not in unreachable for w in t["by"]}
        return unreachable

    assess()
    # A /regex/ entry lists, of the sites it matches, those no test exercises.
    for e in entries:
        if e["regex"]:
            kept = [s for s in e["sites"] if not (s["by"] or s["by_own"])]
            for s in e["sites"]:
                if s not in kept:
                    s["entries"].remove(e)
            e["sites"] = kept
            if not kept:
                failures.append(
                    f"{os.path.basename(ALLOW)}:{e['line']}: every site its /regex/ matches is exercised: "
                    f"remove the entry"
                )
    unreachable = assess()
    where_texts = {}
    for where, t, _ in texts:
        where_texts.setdefault(where, []).append(t)
    name = os.path.basename(ALLOW)
    for s in sites:
        if len(s.get("entries", [])) > 1:
            failures.append(
                f"{shown(s)} is named by {len(s['entries'])} entries of {name} "
                f"(lines {', '.join(str(x['line']) for x in s['entries'])}); keep one"
            )
    for s in sites:
        listed = s.get("entries", [])
        e = listed[0] if listed else None
        if e and e["kind"] == "out":
            if s["by_own"]:
                failures.append(
                    f"{shown(s)} is listed in {name} (line {e['line']}) as out of a deck's reach, but "
                    f"{', '.join(sorted(s['by_own']))} exercises it: remove the entry"
                )
        elif e and s["by"]:
            failures.append(
                f"{shown(s)}: {name} (line {e['line']}) lists it ({e['kind']}), but "
                f"{', '.join(sorted(s['by']))} tells it by its text: remove the entry"
            )
        elif e and e["kind"] == "by":
            texts_of = where_texts.get(e["by"])
            own = words_of(" ".join(s["frags"]))
            if texts_of is None:
                failures.append(
                    f"{shown(s)}: {name} (line {e['line']}) says {e['by']} exercises it: no such case " f"or test"
                )
            elif len(own) >= 3 and not words_of(" ".join(texts_of)) & own:  # a light check of the name
                failures.append(
                    f"{shown(s)}: {name} (line {e['line']}) says {e['by']} exercises it, but no text of "
                    f"{e['by']} shares a word with its message"
                )
            else:
                s["by"] = {e["by"] + " (listed)"}
        elif not e and not s["by"]:
            why = (
                "no test exercises it"
                if s["telling_deck"]
                else "no run of its message's words is its own, so no test can be seen to exercise it"
            )
            failures.append(
                f'{shown(s)}: {why}: "{skeleton(s)}"\n'
                f"     add a tests/badinput/cases deck expecting its message; if no deck can reach it, add "
                f"'FILE | FRAGMENT | REASON' to tests/badinput/{name}; if a test exercises it whose text "
                f"does not tell it, 'FILE | FRAGMENT | by WHERE | REASON'; a deck reaches it but no case "
                f"can yet, 'FILE | FRAGMENT | gap | REASON'"
            )
    if a.report:
        for s in sites:
            listed = [e for e in s.get("entries", []) if e["kind"] != "by"]
            what = ", ".join(sorted(s["by"])) or (
                f"{listed[0]['kind']}: {listed[0]['reason']}" if listed else "NOTHING"
            )
            print(f"{shown(s)}: {what}\n    {skeleton(s)}")
    counts = dict(case=0, test=0, listed=0, out=0, gap=0)
    for s in sites:
        if any(w.endswith("(listed)") for w in s["by"]):
            counts["listed"] += 1
        elif any(w.startswith("case ") for w in s["by"]):
            counts["case"] += 1
        elif s["by"]:
            counts["test"] += 1
        elif s["id"] in unreachable:
            counts["out"] += 1
        elif any(e["kind"] == "gap" for e in s.get("entries", [])):
            counts["gap"] += 1
    for f in failures:
        print("FAIL " + f)
    print(
        f"{len(sites)} refusal sites in packages/: {counts['case']} exercised by a badinput case, "
        f"{counts['test']} by another test, {counts['listed']} by a case or test named in {name}; "
        f"{counts['out']} out of a deck's reach "
        f"({sum(1 for e in entries if e['kind'] == 'out')} entries of {name}); {counts['gap']} known gaps (a deck "
        f"reaches them, no case yet); {len(failures)} failure(s)"
    )
    for e in entries:
        if e["kind"] == "gap":
            print(f"gap: {', '.join(shown(s) for s in e['sites'])}: {e['reason']}")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
