"""Makes examples/georeferencing/mithunnallana_6img.gcps (made up, as the
priors beside it are): the model solved onto those priors, then 4 of its
points seen in 3 or more images taken as surveyed points at their adjusted
position in the priors' frame (rounded to the centimetre), 3 as control and
1 as check, with their measurements from the model's tracks.

    python3 scripts/make_gcp_example.py DBA MODEL_DIR PRIORS OUT
"""
import os
import subprocess
import sys
import tempfile

dba, model, priors, out = sys.argv[1:5]
with tempfile.TemporaryDirectory() as tmp:
    subprocess.run([dba, "solve", model, "-q", "--camera-priors", priors, "-o", tmp + "/m",
                    "--colmap-format", "text"], check=True, stdout=subprocess.DEVNULL)
    images, points2d = {}, {}
    lines = [l for l in open(tmp + "/m/images.txt") if not l.startswith("#")]
    for head, pts in zip(lines[0::2], lines[1::2]):
        f = head.split()
        images[int(f[0])] = f[9]
        v = pts.split()
        points2d[int(f[0])] = [(float(v[i]), float(v[i + 1])) for i in range(0, len(v), 3)]
    chosen = []
    for l in open(tmp + "/m/points3D.txt"):
        if l.startswith("#"):
            continue
        f = l.split()
        track = [(int(f[i]), int(f[i + 1])) for i in range(8, len(f), 2)]
        if len({i for i, _ in track}) >= 3:
            chosen.append(([float(x) for x in f[1:4]], track))
    step = max(1, len(chosen) // 4)
    chosen = chosen[::step][:4]
with open(out, "w") as o:
    o.write("# Ground control for ../shared/data/colmap/mithunnallana_6img (made up for the example,\n"
            "# like the priors: 4 of the model's points in the priors' frame, metres; made by\n"
            "# scripts/make_gcp_example.py). NAME X Y Z SIGMA_XY SIGMA_Z control|check, then\n"
            "# NAME IMAGE x y (COLMAP's pixels: origin at the top-left corner, y down)\n")
    for n, (xyz, track) in enumerate(chosen):
        name = f"GCP{n + 1}" if n < 3 else "CHK1"
        o.write(f"{name} {xyz[0]:.2f} {xyz[1]:.2f} {xyz[2]:.2f} 0.02 0.03 {'control' if n < 3 else 'check'}\n")
        seen = set()
        for image, idx in track:
            if image in seen:
                continue
            seen.add(image)
            x, y = points2d[image][idx]
            o.write(f"{name} {images[image]} {x:.2f} {y:.2f}\n")
