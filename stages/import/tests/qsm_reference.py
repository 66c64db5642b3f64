#!/usr/bin/env python3
"""Independent reference values for qsm_fixture_test.cpp (see docs/stages/import.md).

Reads the raw QSM tables with Python's csv module (not the C++ parser) and applies the
conversion rules of docs/stages/import.md: continuation = same branch id and branch order,
thickest first; node radii = mean of the cylinders meeting at a node; DBH = 2 x the trunk
radius interpolated where the trunk first reaches 1.3 m above its base (libs/tree's stats).
Usage: stages/import/tests/qsm_reference.py [DATA_DIR]   (default ../shared/data)
"""
import csv
import math
import os
import sys


def load_simpleforest(path):
    rows = list(csv.reader(open(path), skipinitialspace=True))
    ix = {name.strip(): i for i, name in enumerate(rows[0])}
    cyl = []
    for r in rows[1:]:
        g = lambda k: float(r[ix[k]])
        cyl.append(dict(id=int(g('ID')), par=int(g('parentID')),
                        s=(g('startX'), g('startY'), g('startZ')), e=(g('endX'), g('endY'), g('endZ')),
                        r=g('radius'), b=int(g('branchID')), o=int(g('branchOrder'))))
    index = {c['id']: i for i, c in enumerate(cyl)}
    for c in cyl:
        c['p'] = index.get(c['par'], -1)
    return cyl


def load_treeqsm(path):
    lines = [l.rstrip('\n') for l in open(path) if not l.startswith('#')]
    ix = {name: i for i, name in enumerate(lines[0].split('\t'))}
    cyl = []
    for r in (l.split('\t') for l in lines[1:]):
        g = lambda k: float(r[ix[k]])
        s = (g('start_x'), g('start_y'), g('start_z'))
        a = (g('axis_x'), g('axis_y'), g('axis_z'))
        n = math.sqrt(sum(x * x for x in a))
        e = tuple(s[i] + a[i] / n * g('length') for i in range(3))
        cyl.append(dict(s=s, e=e, r=g('radius'), p=int(g('parent')) - 1,
                        b=int(g('branch')), o=int(g('BranchOrder'))))
    return cyl


def analyse(cyl):
    n = len(cyl)
    root = next(i for i, c in enumerate(cyl) if c['p'] < 0)
    children = [[] for _ in cyl]
    for i, c in enumerate(cyl):
        if c['p'] >= 0:
            children[c['p']].append(i)
    nxt = [-1] * n
    for p in range(n):
        for c in children[p]:
            if cyl[c]['b'] == cyl[p]['b'] and cyl[c]['o'] == cyl[p]['o'] and \
                    (nxt[p] < 0 or cyl[c]['r'] > cyl[nxt[p]]['r']):
                nxt[p] = c
    z = [c['s'][2] for c in cyl] + [c['e'][2] for c in cyl]
    trunk = [root]
    while nxt[trunk[-1]] >= 0:
        trunk.append(nxt[trunk[-1]])
    heights = [cyl[root]['s'][2]] + [cyl[c]['e'][2] for c in trunk]
    radii = [cyl[trunk[0]]['r']] + [
        (cyl[c]['r'] + cyl[trunk[k + 1]]['r']) / 2 if k + 1 < len(trunk) else cyl[c]['r']
        for k, c in enumerate(trunk)]
    target = heights[0] + 1.3
    dbh = dbh_cylinder = None
    for k in range(1, len(heights)):
        if heights[k - 1] < target <= heights[k]:
            t = (target - heights[k - 1]) / (heights[k] - heights[k - 1])
            dbh = 2 * (radii[k - 1] + (radii[k] - radii[k - 1]) * t)
            dbh_cylinder = 2 * cyl[trunk[k - 1]]['r']
            break
    length = 0.0
    for i, c in enumerate(cyl):
        continues = c['p'] >= 0 and nxt[c['p']] == i
        length += math.dist(cyl[c['p']]['e'] if continues else c['s'], c['e'])
    return dict(cylinders=n, height=max(z) - heights[0], height_minmax=max(z) - min(z),
                dbh=dbh, dbh_cylinder=dbh_cylinder,
                max_order=max(c['o'] for c in cyl) - cyl[root]['o'],
                branches=1 + sum(1 for p in range(n) for c in children[p] if c != nxt[p]),
                total_length=length)


def main():
    data = sys.argv[1] if len(sys.argv) > 1 else os.environ.get('SYLVA_DATA_DIR', '../shared/data')
    qsm = os.path.join(data, 'qsm')
    for name in ['canopyHydro_5_SmallTree.csv', 'canopyHydro_example_tree.csv', 'rTwig_QSM.csv']:
        print(name, analyse(load_simpleforest(os.path.join(qsm, name))))
    name = 'rTwig_QSM_mat_TreeQSM241_cylinders.tsv'
    print(name, analyse(load_treeqsm(os.path.join(qsm, name))))


if __name__ == '__main__':
    main()
