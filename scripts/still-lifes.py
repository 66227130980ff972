#!/usr/bin/env python3
"""Still lifes: a third family of lens scenes for the adaptive floors (issue
14), written from the scene format alone, outside the scene generator's code
and the repository's scenes.

    python3 scripts/still-lifes.py FIRST COUNT DIR

writes DIR/sFIRST.scene .. and prints their paths, comma-separated, for
LENSRAY_CAMPAIGN_SCENES (BENCHMARKS.md, twenty-seventh round); with a
fourth argument `foreground`, DIR/fFIRST.scene .., the same still lifes
with one or two solids just before the lens (twenty-ninth round):

    mkdir -p /tmp/still
    LENSRAY_CAMPAIGN_SCENES=$(python3 scripts/still-lifes.py 1 40 /tmp/still) \\
        bash scripts/adaptive-campaign.sh 0 0 320 1024

Scene s (Python's random.Random(s)) is what a photographer sets up: a
checkered table top or floor, three to seven solids of the named materials
or of shiny custom ones (Phong exponents up to 128: small, bright highlights,
which far out of focus reach a pixel through a sliver of the lens), one to
three lights, sometimes shadows, and a camera focused the way a camera is
(`focus_on` a solid, or `focus_distance`), opened by `f_number` 1.4 to 8 or a
`radius`, sometimes with aperture blades, at a `point` of 10 to 100.
"""
import os
import random
import sys

MATERIALS = ['gold', 'copper', 'silver', 'brass', 'bronze', 'chrome', 'pewter', 'emerald', 'jade', 'ruby']
SHAPES = ['sphere', 'cube', 'cylinder', 'cone']


def f(x):
    return '%.4g' % x


def scene(s):
    rng = random.Random(s)
    out = ['# still life %d (scripts/still-lifes.py)' % s]
    out.append('width %s' % f(rng.uniform(6, 12)))
    out.append('aspect_ratio 1.33')
    out.append('image_distance %s' % f(rng.uniform(5, 10)))
    height = rng.uniform(0, 3)
    out.append('lens_position 0 %s 0' % f(height))
    out.append('look %s %s -1' % (f(rng.uniform(-0.2, 0.2)), f(-rng.uniform(0, 0.4))))
    out.append('up 0 1 0')
    out.append('point %d' % rng.choice([rng.randint(10, 40), rng.randint(10, 100)]))
    a = rng.uniform(0.05, 0.6)
    out.append('ambient_light %s %s %s' % (f(a), f(a * rng.uniform(0.7, 1)), f(a * rng.uniform(0.6, 1))))
    for _ in range(rng.randint(1, 3)):
        out.append('light_position %s %s %s' % (f(rng.uniform(-8, 8)), f(rng.uniform(0, 8)), f(-rng.uniform(-2, 20))))
        k = rng.choice([0.3, 0.6, 1, 1.5, 2.5])
        out.append('light_intensity %s %s %s' % (f(k), f(k * rng.uniform(0.7, 1)), f(k * rng.uniform(0.6, 1))))
    if rng.random() < 0.4:
        out.append('shadows on')
    # The table: a checkered plane 1 to 4 below the lens.
    out += ['object plane', 'Ka 0.1 0.1 0.1',
            'Kd %s %s %s' % (f(rng.uniform(0.2, 0.8)), f(rng.uniform(0.2, 0.8)), f(rng.uniform(0.2, 0.8))),
            'Ks %s' % ' '.join([f(rng.uniform(0, 0.5))] * 3), 'shine %s' % f(rng.uniform(1, 30)),
            'texture %s' % f(rng.choice([0, 0.5, 1, 1, 2])), 'total_transformation 2', 'rotate x -90',
            'translate 0 %s 0' % f(-(height + rng.uniform(1, 4)))]
    n = rng.randint(3, 7)
    depths = []
    for _ in range(n):
        shape = rng.choice(SHAPES)
        z = -rng.uniform(3, 30)
        depths.append(z)
        size = rng.uniform(0.3, 2) * (1 + -z / 20)
        if rng.random() < 0.5:
            out.append('object %s %s' % (shape, rng.choice(MATERIALS)))
        else:
            out.append('object %s' % shape)
            out.append('Ka %s' % ' '.join(f(rng.uniform(0, 0.3)) for _ in range(3)))
            out.append('Kd %s' % ' '.join(f(rng.uniform(0, 0.9)) for _ in range(3)))
            ks = rng.uniform(0.3, 1)
            out.append('Ks %s %s %s' % (f(ks), f(ks), f(ks)))
            out.append('shine %s' % f(rng.choice([5, 20, 60, 128])))
        if rng.random() < 0.2:
            out.append('texture %s' % f(rng.uniform(0.1, 1)))
        out.append('total_transformation 3')
        out.append('scale %s %s %s' % (f(size), f(size * rng.uniform(0.6, 1.6)), f(size)))
        out.append('rotate %s %d' % (rng.choice('xyz'), rng.randint(0, 90)))
        out.append('translate %s %s %s' % (f(rng.uniform(-0.5, 0.5) * -z), f(rng.uniform(-1, 1.5)), f(z)))
    # Focus as a camera does: on a solid (objects 2.. are the solids), or at a distance.
    if rng.random() < 0.6:
        out.append('focus_on %d' % rng.randint(2, n + 1))
    else:
        out.append('focus_distance %s' % f(rng.uniform(2, 30)))
    if rng.random() < 0.6:
        out.append('f_number %s' % f(rng.choice([1.4, 2, 2.8, 4, 5.6, 8])))
    else:
        out.append('radius %s' % f(rng.uniform(0.05, 1)))
    if rng.random() < 0.3:
        out.append('aperture_blades %d' % rng.choice([5, 6, 7, 8, 9]))
        out.append('aperture_rotation %d' % rng.randint(0, 90))
    return '\n'.join(out) + '\n'


def foreground(s, text):
    """Still life s with one or two solids just before the lens, far out of
    focus across part of the view (a photographer's foreground blur): its own
    random stream, so the still life behind is scene(s) as it is."""
    rng = random.Random(1000003 * s + 17)
    field = {}
    for line in text.splitlines():
        k = line.split()
        if k and k[0] in ('width', 'image_distance'):
            field[k[0]] = float(k[1])
        if k and k[0] == 'lens_position':
            field['height'] = float(k[2])
    # Half the view's width a unit of depth.
    half = field['width'] / 2 / field['image_distance']
    out = [text.rstrip('\n')]
    for _ in range(rng.randint(1, 2)):
        z = -rng.uniform(0.4, 4)
        size = rng.uniform(0.05, 0.5) * -z * half
        shape = rng.choice(SHAPES)
        if rng.random() < 0.5:
            out.append('object %s %s' % (shape, rng.choice(MATERIALS)))
        else:
            out.append('object %s' % shape)
            out.append('Kd %s' % ' '.join(f(rng.uniform(0, 0.9)) for _ in range(3)))
            ks = rng.uniform(0, 1)
            out.append('Ks %s %s %s' % (f(ks), f(ks), f(ks)))
            out.append('shine %s' % f(rng.choice([5, 20, 60, 128])))
        if rng.random() < 0.2:
            out.append('texture %s' % f(rng.uniform(0.05, 0.5) * size))
        out.append('total_transformation 3')
        out.append('scale %s %s %s' % (f(size), f(size * rng.uniform(0.6, 1.6)), f(size)))
        out.append('rotate %s %d' % (rng.choice('xyz'), rng.randint(0, 90)))
        # Up to the view's edge, the solid's centre in front of the lens by -z.
        out.append('translate %s %s %s' % (f(rng.uniform(-1, 1) * -z * half),
                                           f(field['height'] + rng.uniform(-0.75, 0.75) * -z * half), f(z)))
    return '\n'.join(out) + '\n'


def main():
    first, count, out = int(sys.argv[1]), int(sys.argv[2]), sys.argv[3]
    fore = len(sys.argv) > 4 and sys.argv[4] == 'foreground'
    names = []
    for s in range(first, first + count):
        p = os.path.join(out, ('f%d.scene' if fore else 's%d.scene') % s)
        with open(p, 'w') as fh:
            fh.write(foreground(s, scene(s)) if fore else scene(s))
        names.append(p)
    print(','.join(names))


if __name__ == '__main__':
    main()
