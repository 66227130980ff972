#!/usr/bin/env python3
"""Mutants of the repository's lens scenes: a second family of scenes for the
adaptive floors (issue 14), made outside the scene generator's code.

    python3 scripts/mutate-scenes.py FIRST COUNT DIR

writes DIR/mFIRST.scene .. and prints their paths, comma-separated, for
LENSRAY_CAMPAIGN_SCENES (BENCHMARKS.md, twenty-sixth round):

    mkdir -p /tmp/mut
    LENSRAY_CAMPAIGN_SCENES=$(python3 scripts/mutate-scenes.py 1 40 /tmp/mut) \
        bash scripts/adaptive-campaign.sh 0 0 320 1024

Mutant s takes one of scenes/ and host-tests/extra-scenes/ (Python's
random.Random(s)), drops its camera's sampling lines, scales some lights and
depths, and sets a `point` of 10 to 90, a lens radius of 0.05 to 1.2, often a
focus distance, an aperture polygon and shadows, and up to four lamps (small
spheres 2 to 30 times white by their Ka).

The focus distance is written first, so a base's own `focal_length` or
`focus_on`, which comes after it, stands (the last focus statement does):
only mutants of pinhole-shapes and hand-{grazing,lamp-grid,macro-bokeh,
near-focus}, which have neither, are refocused. Left so, so that mutants
1-120 stay the scenes measured in BENCHMARKS.md; scripts/still-lifes.py
sets its focus last. With a fourth argument `--focus-last` the same
mutants are written with the focus distance last, where it stands: the
family refocused (BENCHMARKS.md, twenty-seventh round).
"""
import glob
import os
import random
import sys

seed0 = int(sys.argv[1]); count = int(sys.argv[2]); out = sys.argv[3]
focus_last = sys.argv[4:] == ['--focus-last']
root = os.path.join(os.path.dirname(os.path.abspath(__file__)), '..')
bases = sorted(glob.glob(os.path.join(root, 'scenes/*.scene')) + glob.glob(os.path.join(root, 'host-tests/extra-scenes/hand-*.scene')) + glob.glob(os.path.join(root, 'host-tests/extra-scenes/camera-*.scene')))
DROP = ('point', 'radius', 'focus_distance', 'aperture_blades', 'aperture_rotation', 'sampler', 'adaptive')
names = []
for s in range(seed0, seed0 + count):
    rng = random.Random(s)
    base = rng.choice(bases)
    lines = open(base).read().splitlines()
    kept = []
    for l in lines:
        w = l.split()
        if w and w[0] in DROP:
            continue
        if w and w[0] == 'light_intensity' and rng.random() < 0.5:
            k = rng.choice([0.3, 0.6, 1.5, 2.5])
            l = 'light_intensity ' + ' '.join('%.3g' % (float(x) * k) for x in w[1:4])
        if w and w[0] == 'translate' and rng.random() < 0.3:
            v = [float(x) for x in w[1:4]]
            v[2] *= rng.choice([0.6, 1.4, 2.0])
            l = 'translate %.3g %.3g %.3g' % tuple(v)
        kept.append(l)
    extra = ['# mutant %d of %s' % (s, os.path.basename(base))]
    extra.append('point %d' % rng.randint(10, 90))
    extra.append('radius %.3g' % rng.choice([0.05, 0.1, 0.2, 0.3, 0.5, 0.8, 1.2]))
    focus = []
    if rng.random() < 0.6:
        (focus if focus_last else extra).append('focus_distance %.3g' % rng.uniform(1.5, 25))
    if rng.random() < 0.4:
        extra.append('aperture_blades %d' % rng.choice([3, 5, 6, 7, 8, 9, 12]))
        extra.append('aperture_rotation %d' % rng.randint(0, 90))
    if rng.random() < 0.3:
        extra.append('shadows on')
    lamps = []
    for _ in range(rng.choice([0, 0, 1, 2, 4])):
        k = rng.uniform(2, 30)
        lamps += ['object sphere', 'Ka %.3g %.3g %.3g' % (k, k * rng.uniform(0.3, 1), k * rng.uniform(0.2, 1)), 'Kd 0 0 0',
                  'total_transformation 2', 'scale %.3g %.3g %.3g' % ((rng.uniform(0.03, 0.3),) * 3),
                  'translate %.3g %.3g %.3g' % (rng.uniform(-4, 4), rng.uniform(-2, 3), -rng.uniform(2, 25))]
    text = '\n'.join(extra + kept + lamps + focus) + '\n'
    p = '%s/m%d.scene' % (out, s)
    open(p, 'w').write(text)
    names.append(p)
print(','.join(names))
