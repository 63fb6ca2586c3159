"""A URDF's inertias checked against its geometry from Python, as `momentlmi check`
does, and repaired where they are not physically consistent. Run from the
repository's root:

    python python/examples/check_urdf.py [robots/panda/panda.urdf] [--repair OUT.urdf]
"""

import argparse

import momentlmi as m

ap = argparse.ArgumentParser()
ap.add_argument("urdf", nargs="?", default="robots/panda/panda.urdf")
ap.add_argument("--repair", help="where to write a repaired copy")
a = ap.parse_args()

for link in m.check_urdf(a.urdf):
    inside = {True: "inside its geometry", False: "NOT inside its geometry", None: "no geometry"}
    print(f"{link['name']:<24} {link['mass']:8.3f} kg  {link['status']:<20} {inside[link['realizable_in_geometry']]}")
if a.repair:
    _, repaired = m.repair_urdf(a.urdf, a.repair)
    print(f"wrote {a.repair}; repaired: {', '.join(repaired) or 'none'}")
