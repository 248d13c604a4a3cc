"""Memory of a slide does not grow with its slips (issue 22): contact_slide on a Regime III
contact with the relaxation path of every slip written ([output] path_frames = 1), slid once to
a distance and once to about twice as many slips: the peak resident memory of the second run
may exceed the first's by at most 10 MB (allocator and library noise), whereas every frame
held, or every written chunk kept in a cache, adds megabytes per slip here (a path of 32
frames of this 53 x 53 block is about 6 MB of fields). The slips are relaxed by the flow (the
tools' only slip solvers are path-faithful, issue 21): 17 and 46 slips to Dx = 2.5 and 3.4 d, in
about 20 and 60 s.

Usage: memory_flat.py CONTACT_SLIDE WORK_DIR
"""
import os
import re
import resource
import subprocess
import sys

contact_slide, work = sys.argv[1], sys.argv[2]
os.makedirs(work, exist_ok=True)
scene = os.path.join(work, "scene.toml")
with open(scene, "w") as f:
    f.write("[contact]\na = 24.0\nR = 40.0\n[slide]\npath_frame_every = 5\n"
            "[output]\npath_frames = 1\n[fft]\nthreads = 1\n")


def run(distance):
    """Peak resident memory (MB) and slip events of one slide, in a process of its own."""
    out = os.path.join(work, f"d{distance}")
    code = (
        "import resource, subprocess, sys\n"
        "r = subprocess.run(sys.argv[1:], capture_output=True, text=True)\n"
        "sys.stdout.write(r.stdout)\n"
        "print('maxrss_kb', resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss)\n"
        "sys.exit(r.returncode)\n"
    )
    r = subprocess.run(
        [sys.executable, "-c", code, contact_slide, scene, "--distance", str(distance), "--out", out],
        capture_output=True, text=True, check=True)
    rss = int(re.search(r"maxrss_kb (\d+)", r.stdout).group(1)) / 1024
    slips = int(re.search(r"slip events (\d+)", r.stdout).group(1))
    paths = os.path.getsize(os.path.join(out, "snapshots", "paths.nc")) / 1e6
    return rss, slips, paths


rss1, slips1, paths1 = run(2.5)
rss2, slips2, paths2 = run(3.4)
print(f"{slips1} slips: {rss1:.1f} MB peak, paths.nc {paths1:.1f} MB; "
      f"{slips2} slips: {rss2:.1f} MB peak, paths.nc {paths2:.1f} MB")
assert slips2 >= 2 * slips1 and slips1 >= 4, (slips1, slips2)
assert paths2 > 1.5 * paths1, (paths1, paths2)  # the paths were written
assert rss2 <= rss1 + 10.0, (rss1, rss2)
