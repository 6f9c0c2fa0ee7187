#!/usr/bin/env python3
"""Runs the CTest tests of a build one process per GoogleTest executable instead of one per test
(tools/sanitize-and-fuzz.sh, docs/fuzzing.md): under the sanitizers each process costs about half a
second to start and to leak-check at its exit, and the suite has hundreds of short tests.

    run_grouped.py BUILD_DIR JOBS [--separate REGEX] [ctest selection arguments, e.g. -E REGEX]

CTest itself selects the tests (`ctest --show-only=json-v1` with the arguments), so the selection
means what it means for ctest. Tests of one executable run in one process with a --gtest_filter
naming each of them; tests that are not GoogleTest cases, and those whose names match the
--separate regex (timing-sensitive ones), run through ctest, one by one. JOBS
processes run at once. Prints the log of every process that failed and exits 1 if any did."""
import collections
import concurrent.futures
import json
import os
import re
import subprocess
import sys
import time

TIMEOUT_S = 1800  # a whole executable's tests; ctest gives each test 600 s


def selected_tests(build, ctest_args):
    shown = subprocess.run(["ctest", "--show-only=json-v1", *ctest_args], cwd=build, check=True,
                           capture_output=True, text=True).stdout
    return json.loads(shown)["tests"]


def group(tests, build, separate):
    """{(executable, working directory): [test names]} for GoogleTest cases, and the other names."""
    by_executable, others = collections.OrderedDict(), []
    for test in tests:
        command = test.get("command", [])
        filters = [a for a in command[1:] if a.startswith("--gtest_filter=")]
        if not command or not filters or (separate and re.search(separate, test["name"])):
            others.append(test["name"])
            continue
        workdir = next((p["value"] for p in test.get("properties", []) if p["name"] == "WORKING_DIRECTORY"), build)
        by_executable.setdefault((command[0], workdir), []).append(filters[0][len("--gtest_filter="):])
    return by_executable, others


def run_executable(executable, workdir, names):
    start = time.monotonic()
    try:
        result = subprocess.run([executable, "--gtest_filter=" + ":".join(names)], cwd=workdir,
                                capture_output=True, text=True, timeout=TIMEOUT_S)
        ok, log = result.returncode == 0, result.stdout + result.stderr
        # every selected test ran: a name the filter does not match would otherwise pass unseen
        ran = re.search(r"^\[==========\] (\d+) tests? from .* ran", result.stdout, re.MULTILINE)
        if ok and (not ran or int(ran.group(1)) != len(names)):
            ok, log = False, f"{len(names)} tests selected, {ran.group(1) if ran else 'none'} ran\n{log}"
    except subprocess.TimeoutExpired as e:
        ok, log = False, f"{executable}: still running after {TIMEOUT_S} s\n{e.stdout or ''}"
    return os.path.basename(executable), len(names), ok, log, time.monotonic() - start


def run_through_ctest(build, name):
    start = time.monotonic()
    result = subprocess.run(["ctest", "--output-on-failure", "-R", "^" + name.replace(".", "[.]") + "$"], cwd=build,
                            capture_output=True, text=True)
    return name, 1, result.returncode == 0, result.stdout + result.stderr, time.monotonic() - start


def main():
    if len(sys.argv) < 3:
        sys.exit(__doc__)
    build, jobs, ctest_args = sys.argv[1], int(sys.argv[2]), sys.argv[3:]
    separate = None
    if ctest_args[:1] == ["--separate"]:
        separate, ctest_args = ctest_args[1], ctest_args[2:]
    by_executable, others = group(selected_tests(build, ctest_args), build, separate)
    if not by_executable and not others:
        sys.exit(f"run_grouped.py: ctest {' '.join(ctest_args)} selects no test in {build}")
    # the executables with the most tests first, so that the longest do not start last
    work = sorted(by_executable.items(), key=lambda item: -len(item[1]))
    failed, count, start = [], 0, time.monotonic()
    with concurrent.futures.ThreadPoolExecutor(max_workers=jobs) as pool:
        futures = [pool.submit(run_executable, exe, workdir, names) for (exe, workdir), names in work]
        futures += [pool.submit(run_through_ctest, build, name) for name in others]
        for future in concurrent.futures.as_completed(futures):
            what, tests, ok, log, seconds = future.result()
            count += tests
            print(f"{'passed' if ok else 'FAILED'} {what}: {tests} tests, {seconds:.1f} s", flush=True)
            if not ok:
                failed.append((what, log))
    for what, log in failed:
        print(f"==== {what}\n{log}")
    print(f"{count} tests in {len(futures)} processes, {time.monotonic() - start:.0f} s; "
          f"{len(failed)} processes failed")
    sys.exit(1 if failed else 0)


if __name__ == "__main__":
    main()
