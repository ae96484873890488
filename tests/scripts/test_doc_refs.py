#!/usr/bin/python3
"""References to the documentation resolve: every `docs/<name>.md` named in the repository's files
exists, and every section or bullet quoted after it (`docs/lap.md "Mesh"`, `docs/lap.md, "Mesh"`,
`docs/lap.md ("Mesh"`, `docs/lap.md \\"Mesh\\"` inside a C++ string, `docs/lap.md "A", "B"`, a
name broken over a comment's lines) is the start of a markdown heading or of a bold title
(`**...**`) in that file. Case-sensitive; trailing punctuation and runs of white space do not
count. The files scanned are those git knows of (tracked, and new ones not ignored), from the
repository's root; every dangling reference is reported in one failure."""
import os
import re
import subprocess
import unittest

ROOT = os.path.abspath(os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", ".."))
SELF = os.path.relpath(os.path.abspath(__file__), ROOT)

# A comment's continuation on the next line: its marker and the white space around it.
_NEXT_LINE = r"[ \t]*\n[ \t]*(?:(?://+|#+|\*|--|;+)[ \t]*)?"
_DOC = re.compile(r"(?<![\w/.-])docs/((?:[\w.-]+/)*[\w.-]+\.md)\b")
# Between the file and its first quoted name: a comma or an opening bracket, white space, at most
# one line break (with a comment marker after it).
_GAP = re.compile(r"[ \t]*[,(]?(?:" + _NEXT_LINE + r"|[ \t]*)")
_QUOTE = re.compile(r'\\?"')
# A quoted name: no quote, at most one line break (a comment's continuation), at most 150 characters.
_NAME = re.compile(r'([^"\\\n]{1,150}?(?:' + _NEXT_LINE + r'[^"\\\n]{1,150}?)?)\\?"')
# Between two names of one list: a comma, white space, perhaps a line break.
_LIST = re.compile(r"[ \t]*,(?:" + _NEXT_LINE + r"|[ \t]*)")
_COMMENT_BREAK = re.compile(_NEXT_LINE)
_TRAILING = ".,:;!?"


def normalise(name):
    """White space runs as one space, a comment's line break as one space, no trailing punctuation."""
    name = _COMMENT_BREAK.sub(" ", name)
    return " ".join(name.split()).rstrip(_TRAILING).strip()


def titles(markdown):
    """The headings and bold titles of a markdown text, normalised."""
    found = [m.group(1) for m in re.finditer(r"^#{1,6}[ \t]+(.+?)[ \t#]*$", markdown, re.M)]
    # Bold: from `**` before a non-space to the next `**` after one, within a paragraph.
    found += [m.group(1) for m in re.finditer(r"\*\*(\S(?:[^\n]|\n(?![ \t]*\n))*?)(?<=\S)\*\*", markdown)]
    return [normalise(t) for t in found]


def references(text):
    """(line, document, [quoted names]) for every `docs/<name>.md` in `text`."""
    for doc in _DOC.finditer(text):
        names = []
        pos = doc.end()
        gap = _GAP.match(text, pos)
        quote = _QUOTE.match(text, gap.end())
        # A path that is itself quoted (`open("docs/lap.md", "r")`) is followed by its closing quote,
        # not by a name.
        quoted_path = text[max(0, doc.start() - 1):doc.start()] == '"'
        if quote and not quoted_path:
            pos = quote.end()
            while True:
                name = _NAME.match(text, pos)
                if not name:
                    break
                names.append(normalise(name.group(1)))
                pos = name.end()
                sep = _LIST.match(text, pos)
                nxt = _QUOTE.match(text, sep.end()) if sep else None
                if not nxt:
                    break
                pos = nxt.end()
        yield text.count("\n", 0, doc.start()) + 1, doc.group(1), names


def dangling(files, read_doc):
    """Every reference of `files` ({path: text}) that does not resolve, as 'path:line: ...' lines.
    read_doc(name) gives the text of docs/<name>.md, or None when there is no such file."""
    cache = {}
    problems = []
    for path in sorted(files):
        for line, doc, names in references(files[path]):
            if doc not in cache:
                text = read_doc(doc)
                cache[doc] = None if text is None else titles(text)
            known = cache[doc]
            if known is None:
                problems.append('%s:%d: docs/%s does not exist' % (path, line, doc))
                continue
            for name in names:
                if name and not any(title.startswith(name) for title in known):
                    problems.append('%s:%d: docs/%s has no heading or bold title starting "%s"'
                                    % (path, line, doc, name))
    return problems


def repository_files():
    """{path: text} of the files git knows of (tracked, and new ones not ignored), text files only."""
    listing = subprocess.run(["git", "ls-files", "-z", "--cached", "--others", "--exclude-standard"],
                             cwd=ROOT, capture_output=True, check=True).stdout.decode()
    files = {}
    for path in sorted(set(p for p in listing.split("\0") if p)):
        full = os.path.join(ROOT, path)
        if path == SELF or not os.path.isfile(full):
            continue
        try:
            with open(full, encoding="utf-8") as handle:
                files[path] = handle.read()
        except UnicodeDecodeError:
            continue  # not text
    return files


def read_repository_doc(name):
    path = os.path.join(ROOT, "docs", name)
    if not os.path.isfile(path):
        return None
    with open(path, encoding="utf-8") as handle:
        return handle.read()


class MatcherTest(unittest.TestCase):
    """The matcher on a small in-memory repository."""
    DOC = "# Guide\n\n## Mesh (`mesh.h`; measured)\n- **A price on rolling the bike** (session 25).\n"

    def check(self, files):
        docs = {"guide.md": self.DOC}
        return dangling(files, docs.get)

    def test_one_resolving_and_one_dangling_reference(self):
        problems = self.check({"a.md": 'See docs/guide.md "Mesh" and docs/guide.md, "Missing part".\n'})
        self.assertEqual(problems, ['a.md:1: docs/guide.md has no heading or bold title starting "Missing part"'])

    def test_forms_that_resolve(self):
        files = {
            "b.cc": '// (docs/guide.md "A price on rolling\n// the bike").\n'
                    'const char* s = "(docs/guide.md \\"Mesh\\")";\n',
            "c.md": 'docs/guide.md ("Mesh"), docs/guide.md\n  "Mesh", "A price on rolling the bike"; '
                    'docs/guide.md: [docs/guide.md](docs/guide.md)\n',
            "d.yaml": 'x: 1  # docs/guide.md "A price on rolling the bike."\n',
        }
        self.assertEqual(self.check(files), [])

    def test_a_missing_file_and_a_dangling_second_name(self):
        problems = self.check({"e.sh": '# docs/other.md\n# docs/guide.md "Mesh",\n# "Nothing"\n'})
        self.assertEqual(problems, ["e.sh:1: docs/other.md does not exist",
                                    'e.sh:2: docs/guide.md has no heading or bold title starting "Nothing"'])

    def test_case_counts_and_a_string_holding_the_file_is_no_reference(self):
        self.assertEqual(len(self.check({"f.md": 'docs/guide.md "mesh"\n'})), 1)
        self.assertEqual(self.check({"g.py": 'open("docs/guide.md", "r")\n'}), [])


class RepositoryTest(unittest.TestCase):
    def test_every_documentation_reference_resolves(self):
        try:
            files = repository_files()
        except (OSError, subprocess.CalledProcessError) as error:
            self.skipTest("not a git checkout: %s" % error)
        problems = dangling(files, read_repository_doc)
        if problems:
            self.fail("%d dangling documentation references:\n%s" % (len(problems), "\n".join(problems)))


if __name__ == "__main__":
    unittest.main()
