#!/usr/bin/env python3
"""Doxygen input filter of the Markdown pages (cmake/Doxyfile.in, FILTER_PATTERNS).

    doxygen_md_filter.py PAGE... FILE

Prints FILE with each relative link to a Markdown file that is not one of the PAGEs (file names of
the pages Doxygen reads) turned into its text and the file's path in the repository, "text
(`docs/user/parameters.md`)" (the path alone when the text names the file): Doxygen would report
such a link as an unresolved reference. A link to a PAGE loses its #anchor (Doxygen links the
page). Lines keep their numbers, so warnings point at the source.
"""
import os
import re
import sys

LINK = re.compile(r"(?<!!)\[((?:[^\[\]]|\[[^\]]*\])*)\]\(\s*([^)\s#]+\.md)(#[^)\s]*)?\s*\)")


def main():
    pages, path = set(sys.argv[1:-1]), sys.argv[-1]
    here = os.path.dirname(os.path.abspath(path))
    root = os.path.normpath(os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))

    def rewrite(m):
        text, target = m.group(1), m.group(2)
        if "://" in target:
            return m.group(0)
        if os.path.basename(target) in pages and os.path.dirname(os.path.normpath(os.path.join(here, target))) == here:
            return "[%s](%s)" % (text, target)
        where = os.path.relpath(os.path.normpath(os.path.join(here, target)), root)
        if os.path.basename(target) in text:
            return "`%s`" % where
        return "%s (`%s`)" % (text, where)

    with open(path, encoding="utf-8") as f:
        sys.stdout.write(LINK.sub(rewrite, f.read()))


if __name__ == "__main__":
    main()
