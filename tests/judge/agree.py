#!/usr/bin/env python3
"""The CGAL judge against stltopo: for every STL given, `stltopo info --json --intersections
--defects` must list the same zero-area triangles, duplicate groups and intersecting pairs
(with their kinds) as `stltopo_cgal_judge`. Files that neither can read are skipped.

  agree.py STLTOPO_CLI JUDGE FILE...
"""
import json
import subprocess
import sys


def compare(cli, judge, f):
    """None when neither program reads f; else (the judge's pair count, the differences)."""
    j = subprocess.run([judge, f], capture_output=True, text=True)
    s = subprocess.run([cli, 'info', '--json', '--intersections', '--defects', '--max-defects', '4000000000', f],
                       capture_output=True, text=True)
    if j.returncode != 0 or s.returncode != 0:
        if (j.returncode == 0) != (s.returncode == 0):
            return 0, ['judge exit %d, stltopo exit %d' % (j.returncode, s.returncode)]
        return None
    lines = j.stdout.splitlines()
    head = json.loads(lines[0])
    want_pairs = [tuple(l.split()) for l in lines[1:]]
    got = json.loads(s.stdout)
    d = got['defects']
    got_pairs = [(str(it['triangles'][0]), str(it['triangles'][1]), it['kind'])
                 for it in d['selfIntersections']['items']]
    problems = []
    if [it['triangle'] for it in d['zeroAreaTriangles']['items']] != head['zeroArea']:
        problems.append('zero-area triangles differ')
    if [it['triangles'] for it in d['duplicateTriangles']['items']] != head['duplicateGroups']:
        problems.append('duplicate groups differ')
    if got_pairs != want_pairs:
        extra = sorted(set(got_pairs) - set(want_pairs))[:5]
        missing = sorted(set(want_pairs) - set(got_pairs))[:5]
        problems.append('pairs differ: %d vs judge %d; only stltopo %s; only judge %s' %
                        (len(got_pairs), len(want_pairs), extra, missing))
    if got['selfIntersections'] != head['pairs'] or not got['intersectionsComplete']:
        problems.append('count %r vs judge %r' % (got['selfIntersections'], head['pairs']))
    return len(want_pairs), problems


def main(cli, judge, files):
    bad = compared = 0
    pairs_total = 0
    for f in files:
        r = compare(cli, judge, f)
        if r is None:
            continue
        pairs, problems = r
        compared += 1
        pairs_total += pairs
        if problems:
            bad += 1
            print('%s: %s' % (f, '; '.join(problems)))
    print('compared %d files (%d pairs) with the CGAL judge: %d differ' % (compared, pairs_total, bad))
    return 1 if bad or compared == 0 else 0


if __name__ == '__main__':
    sys.exit(main(sys.argv[1], sys.argv[2], sys.argv[3:]))
