#!/usr/bin/python3
"""README's getting-started guide, run as written: every ```sh block of its "Getting started"
section, in order, in one shell that stops at the first failing command, on the built tree. HOME is
a fresh folder (the guide's ~/robots lives there); the firmware cache stays the user's, as the
guide's runs would share it. Exit 77 (skipped) when the tree under test is not README's build/
(a sanitizer build), as the guide's scripts build and run build/.

Usage: guide_test.py SOURCE_DIR BINARY_DIR
"""
import os
import re
import subprocess
import sys
import tempfile

SOURCE, BINARY = (os.path.realpath(p) for p in sys.argv[1:3])


def guide_blocks(readme):
    section = re.search(r"^## Getting started\n(.*?)^## ", readme, re.S | re.M)
    if not section:
        sys.exit("README.md has no '## Getting started' section")
    return re.findall(r"^```sh\n(.*?)^```", section.group(1), re.S | re.M)


def main():
    if BINARY != os.path.join(SOURCE, "build"):
        print(f"skipped: the guide builds and runs {SOURCE}/build, and this tree is {BINARY}")
        return 77
    with open(os.path.join(SOURCE, "README.md")) as f:
        blocks = guide_blocks(f.read())
    # Step 1 (set-up and first run), 2 (sear on PATH), 3 (a project of one's own), 4 (outputs),
    # 5 (CI): a guide that lost a step is a guide that changed without its test.
    if len(blocks) != 5:
        print(f"expected the guide's 5 steps as ```sh blocks, found {len(blocks)}")
        return 1
    env = dict(os.environ)
    env["XDG_CACHE_HOME"] = env.get("XDG_CACHE_HOME") or os.path.join(env.get("HOME", "/root"), ".cache")
    env["SEAR_NO_PLOTS"] = "1"  # the guide says nothing of plots; they only cost seconds here
    with tempfile.TemporaryDirectory() as home:
        env["HOME"] = home
        script = "set -euo pipefail\n" + "\n".join(blocks)
        done = subprocess.run(["bash", "-c", script], cwd=SOURCE, env=env, capture_output=True, text=True,
                              timeout=600)
        out = done.stdout + done.stderr
        print(out)
        if done.returncode != 0:
            print(f"the guide stopped with exit code {done.returncode}")
            return 1
        robots = os.path.join(home, "robots")
        checks = [
            ("the reference rover ran", "SEAR run of 'default'" in out),
            ("the new project's expectations held", re.search(r"expectations: (\d+) of \1 passed", out) is not None),
            ("sear test wrote its report with no failure",
             'failures="0"' in open(os.path.join(robots, "report.xml")).read()),
            ("the outputs the guide shows are the new project's",
             "SEAR run of 'mybot'" in done.stdout and "\ntime_s," in done.stdout),
        ]
        failed = [what for what, ok in checks if not ok]
        for what in failed:
            print(f"not seen: {what}")
        return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
