#!/usr/bin/python3
"""One Markdown row per port check of a known-good configuration (docs/port-validation.md,
"Known-good runs"), from what `ppohdem validate --port` printed and wrote.

    /usr/bin/python3 validation/port/known_good_table.py "LABEL=DIR" ...

DIR holds stdout.log (the check's standard output) and report.md (its --out report). A row:
the deterministic tier's largest relative difference (and which quantity), the Chung & Ooi
rows that failed, each scene's largest |PC score| and failing PCs, whether the run of seed 1001
equals the reference machine's bit for bit (the growth diagnostic), and the verdict.
"""
import os
import re
import sys

SCENES = ['settling_bed', 'seed_sample']


def deterministic(lines):
    worst, where, rows = 0.0, '-', 0
    for line in lines:
        m = re.match(r'^(\S+)\s+(.+?)\s+(\S+) \(tolerance (\S+)\) (pass|FAIL)$', line)
        if m:
            rows += 1
            value = float(m.group(3))
            if value >= worst:
                worst, where = value, '%s %s' % (m.group(1), m.group(2).strip())
    return rows, worst, where


def growth(report, scene):
    """'equal' if the seed-1001 run's RMS distance to the reference run is 0 at every frame,
    else the first step where it is not, with the value."""
    if not os.path.exists(report):
        return '-'
    text = open(report).read()
    start = text.find('\n## %s:' % scene)
    if start < 0:
        return '-'
    section = text[start:text.find('\n## ', start + 5) if text.find('\n## ', start + 5) > 0 else len(text)]
    growth_at = section.find('Growth diagnostic')
    if growth_at < 0:
        return '-'
    rows = re.findall(r'^\| (\d+) \| (\S+) \| \S+ \| \S+ \| \S+ \|$', section[growth_at:], re.M)
    if not rows:
        return '-'
    for step, value in rows:
        if float(value) != 0.0:
            return 'differs from step %s (%s m)' % (step, value)
    return 'bitwise equal'


def row(label, folder):
    log = os.path.join(folder, 'stdout.log')
    lines = open(log).read().splitlines() if os.path.exists(log) else []
    rows, worst, where = deterministic(lines)
    analytic = next((l.split(': ', 1)[1] for l in lines if l.startswith('analytic checks')), '-')
    cells = [label]
    cells.append(('%.3g (%s)' % (worst, where) if worst > 0 else '0 (all %d rows)' % rows) if rows else '-')
    cells.append(analytic)
    for scene in SCENES:
        line = next((l for l in lines if l.startswith(scene + ' ')), None)
        if line is None:
            cells.append('-')
            continue
        m = re.search(r'(PASS|FAIL)\s+\(failing PCs: ([^;]*); largest \|score\| (\S+) sigma\)', line)
        cells.append('%s sigma, failing PCs: %s; seed 1001: %s' % (m.group(3), m.group(2), growth(os.path.join(folder, 'report.md'), scene))
                     if m else line)
    verdict = next((l.split(': ', 1)[1] for l in lines if l.startswith('port check: ')), 'no verdict (see %s)' % log)
    cells.append('**%s**' % verdict if verdict != 'PASS' else verdict)
    return '| ' + ' | '.join(cells) + ' |'


def main():
    if len(sys.argv) < 2:
        sys.exit(__doc__)
    print('| configuration | deterministic tier: largest relative difference | Chung & Ooi rows | '
          'settling_bed: largest score | seed_sample: largest score | verdict |')
    print('|---|---|---|---|---|---|')
    for arg in sys.argv[1:]:
        label, _, folder = arg.rpartition('=')
        print(row(label, folder))


if __name__ == '__main__':
    main()
