#!/usr/bin/python3
"""Check that every docs/<file>.md the sources cite exists, and so does every section they name.

Usage: /usr/bin/python3 ci/check-doc-links.py [--root DIR] [--list] [--self-test]

Scanned: README.md, CMakeLists.txt and every text file under core/, reference/, apps/,
validation/, tests/, ci/, cmake/, bindings/, python/ and docs/ (build directories skipped).
Comment prefixes are dropped and lines joined first, so a citation may wrap over lines.

A citation is "docs/<file>.md" (it must exist), optionally followed by section names:
  docs/performance.md "Four contacts at a time"
  docs/performance.md, "What the law's stores cost"      (also: , section "X"; "X" and "Y")
  docs/compat.md §2                                       (a numbered heading "## 2. ...")
  [text](docs/performance.md#dem-engine-issue-7)          (GitHub's anchor of a heading)
A quoted name must be a section of that file: a Markdown heading, or a bold lead that opens a
paragraph or list item ("**Cost.** The checks ..."), compared with case and spacing ignored,
emphasis and code marks and a leading section number dropped; a name may also be the start of
one at a word boundary, so that a long heading may be cited by its first words. Prose after the file name that is not quoted
("docs/reliability.md, findings 4-6") is not checked. Exit status 1 lists every broken one.
"""
import os
import re
import sys
import tempfile

SCANNED_DIRS = ["core", "reference", "apps", "validation", "tests", "ci", "cmake", "bindings",
                "python", "docs"]
SCANNED_FILES = ["README.md", "CMakeLists.txt"]
SKIPPED_DIRS = {".git", "__pycache__", "node_modules"}
TEXT_SUFFIXES = {".cpp", ".hpp", ".h", ".c", ".cc", ".f90", ".F90", ".f", ".py", ".sh", ".cmake",
                 ".txt", ".md", ".toml", ".in", ".ipynb", ".bench", ".yml", ".yaml", ""}

# A line break plus the next line's comment prefix (//, ///, #, *, !, --) becomes one space.
CONTINUATION = re.compile(r"[ \t]*\n[ \t]*(?:(?://+|/\*+|\*+|#+|!+|--)[ \t]*)?")
QUOTE = r'\\?["\u201c\u201d]'
TITLE = QUOTE + r'([^"\u201c\u201d\\\n]{1,200})' + QUOTE
CITATION = re.compile(
    r"docs/(?P<doc>[A-Za-z0-9_.-]+\.md)(?:#(?P<anchor>[A-Za-z0-9_-]+))?"
    r"(?:"
    r"(?:,?\s+(?:sections?\s+)?|,\s*(?:sections?\s+)?)" + TITLE.replace("(", "(?P<title>", 1) +
    r"(?P<more>(?:\s*(?:,|and|or|,\s*and)\s*" + TITLE.replace("(", "(?:", 1) + r")*)"
    r"|\s*,?\s*\u00a7\s*(?P<number>\d+(?:\.\d+)*)"
    r")?")
FOLLOWING_TITLE = re.compile(TITLE)


def normalise(title):
    t = re.sub(r"[*_`]", "", title)
    t = re.sub(r"\s+", " ", t).strip().lower()
    return t.rstrip(".,;:")


HEADING = re.compile(r"^(#{1,6})\s+(.*?)\s*#*\s*$")
BOLD_LEAD = re.compile(r"^\s*(?:[-*+]\s+|\d+\.\s+)?\*\*([^*]+?)\*\*")
SECTION_NUMBER = re.compile(r"^\d+(?:\.\d+)*[a-z]?\.?\s+")


def anchor_of(heading):
    """GitHub's anchor of a Markdown heading: lower case, punctuation dropped, spaces to '-'."""
    a = heading.strip().lower()
    a = re.sub(r"[^\w\- ]", "", a)
    return a.replace(" ", "-")


def anchors_of(path):
    found, fenced = set(), False
    with open(path, encoding="utf-8") as f:
        for line in f:
            if line.lstrip().startswith("```"):
                fenced = not fenced
                continue
            m = None if fenced else HEADING.match(line)
            if m:
                found.add(anchor_of(m.group(2)))
    return found


def headings_of(path):
    """The sections of a file, normalised: headings and bold paragraph leads outside code
    fences, each also without its leading section number."""
    found, fenced = [], False
    with open(path, encoding="utf-8") as f:
        for line in f:
            if line.lstrip().startswith("```"):
                fenced = not fenced
                continue
            if fenced:
                continue
            m = HEADING.match(line) or BOLD_LEAD.match(line)
            if m:
                title = normalise(m.group(m.lastindex))
                found.append(title)
                unnumbered = SECTION_NUMBER.sub("", title)
                if unnumbered != title:
                    found.append(unnumbered)
    return found


def title_exists(title, headings):
    want = normalise(title)
    if want.endswith("...") or want.endswith("\u2026"):
        want = want.rstrip(".\u2026").strip()
    for h in headings:
        if h == want:
            return True
        if h.startswith(want) and not h[len(want)].isalnum():
            return True
    return False


def number_exists(number, headings):
    for h in headings:
        if re.match(re.escape(number) + r"(?:\.|\s|$)", h) or h.startswith("\u00a7" + number):
            return True
    return False


def scanned_files(root):
    for name in SCANNED_FILES:
        p = os.path.join(root, name)
        if os.path.isfile(p):
            yield p
    for d in SCANNED_DIRS:
        top = os.path.join(root, d)
        for dirpath, dirnames, filenames in os.walk(top):
            dirnames[:] = sorted(n for n in dirnames
                                 if n not in SKIPPED_DIRS and not n.startswith("build"))
            for n in sorted(filenames):
                if os.path.splitext(n)[1] in TEXT_SUFFIXES:
                    yield os.path.join(dirpath, n)


def citations_in(path):
    """(line, file, [titles], number) for every docs/*.md citation in one file."""
    try:
        with open(path, encoding="utf-8") as f:
            raw = f.read()
    except (UnicodeDecodeError, OSError):
        return
    # Keep a map from joined offsets back to line numbers.
    joined_parts, line_of, line = [], [], 1
    pos = 0
    for m in CONTINUATION.finditer(raw):
        chunk = raw[pos:m.start()]
        joined_parts.append(chunk)
        line_of.extend([line] * len(chunk))
        joined_parts.append(" ")
        line_of.append(line)
        line += 1
        pos = m.end()
    chunk = raw[pos:]
    joined_parts.append(chunk)
    line_of.extend([line] * len(chunk))
    text = "".join(joined_parts)
    for m in CITATION.finditer(text):
        titles = []
        if m.group("title"):
            titles.append(m.group("title"))
            titles.extend(FOLLOWING_TITLE.findall(m.group("more") or ""))
        yield line_of[m.start()], m.group("doc"), m.group("anchor"), titles, m.group("number")


def check(root, listing=False, out=sys.stdout):
    heading_cache, problems, count = {}, [], 0
    for path in scanned_files(root):
        rel = os.path.relpath(path, root)
        if rel == os.path.join("ci", "check-doc-links.py"):
            continue  # its own examples
        for line, doc, anchor, titles, number in citations_in(path):
            count += 1
            doc_path = os.path.join(root, "docs", doc)
            where = "%s:%d" % (rel, line)
            if listing:
                shown = "; ".join('"%s"' % t for t in titles) + (" §" + number if number else "")
                print("%s: docs/%s%s %s" % (where, doc, "#" + anchor if anchor else "", shown),
                      file=out)
            if not os.path.isfile(doc_path):
                problems.append("%s: docs/%s does not exist" % (where, doc))
                continue
            if doc not in heading_cache:
                heading_cache[doc] = headings_of(doc_path)
            for t in titles:
                if not title_exists(t, heading_cache[doc]):
                    problems.append('%s: docs/%s has no section "%s"' % (where, doc, t))
            if number and not number_exists(number, heading_cache[doc]):
                problems.append("%s: docs/%s has no section §%s" % (where, doc, number))
            if anchor and anchor not in anchors_of(doc_path):
                problems.append("%s: docs/%s has no heading with anchor #%s" % (where, doc, anchor))
    for p in problems:
        print("check-doc-links: " + p, file=out)
    print("check-doc-links: %d citations, %d broken" % (count, len(problems)), file=out)
    return not problems


def self_test():
    """The checker must fail on each kind of broken citation and pass on good ones."""
    good = {
        "docs/a.md": "# A\n## 2. Second part\n### Four contacts at a time (AVX)\n```\n# not a heading\n```\n"
                 "- **Equal particles.** One sentence.\n",
        "core/x.cpp": '// see docs/a.md "Four contacts\n// at a time" and docs/a.md §2\n'
                      '// docs/a.md, section "Second part"; docs/a.md, findings 4-6\n',
        "ci/y.sh": 'echo "docs/a.md \\"four contacts at a time\\""\n',
        "tests/z.cpp": '// docs/a.md, "Equal particles"\n',
        "README.md": "[a](docs/a.md#four-contacts-at-a-time-avx) [b](docs/a.md#2-second-part)\n",
    }
    broken = [
        ("core/b.cpp", "// docs/missing.md\n"),
        ("core/b.cpp", '// docs/a.md "Four contacts at a ti"\n'),   # not at a word boundary
        ("core/b.cpp", '// docs/a.md "Second part" and "Third part"\n'),
        ("core/b.cpp", "// docs/a.md §3\n"),
        ("core/b.cpp", '// docs/a.md "not a heading"\n'),            # inside a code fence
        ("core/b.cpp", '// docs/a.md "One sentence"\n'),             # not bold
        ("README.md", "[a](docs/a.md#four-contacts)\n"),             # no such anchor
    ]

    def make(files):
        d = tempfile.mkdtemp(prefix="check-doc-links-")
        for rel, text in files.items():
            p = os.path.join(d, rel)
            os.makedirs(os.path.dirname(p), exist_ok=True)
            with open(p, "w", encoding="utf-8") as f:
                f.write(text)
        return d

    sink = open(os.devnull, "w")
    ok = check(make(good), out=sink)
    if not ok:
        print("self-test: good citations reported as broken")
        check(make(good))
        return False
    for rel, text in broken:
        files = dict(good)
        files[rel] = text
        if check(make(files), out=sink):
            print("self-test: not caught: %r" % text)
            return False
    print("self-test: %d broken citations caught, the good ones pass" % len(broken))
    return True


def main(argv):
    root = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    listing = False
    i = 1
    while i < len(argv):
        if argv[i] == "--root" and i + 1 < len(argv):
            root = argv[i + 1]
            i += 1
        elif argv[i] == "--list":
            listing = True
        elif argv[i] == "--self-test":
            return 0 if self_test() else 1
        else:
            print(__doc__)
            return 2
        i += 1
    return 0 if check(root, listing) else 1


if __name__ == "__main__":
    sys.exit(main(sys.argv))
