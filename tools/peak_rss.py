"""A child process's own peak memory: ru_maxrss of that process alone.

On Linux a child's ru_maxrss starts at its parent's high-water mark (kept over fork and exec),
so a child of a benchmark script never reads below the script's own peak (tens of MB once numpy
is loaded). `launch` starts the command through a small launcher (a fresh `python -I -S -c
LAUNCHER`, about 5 MB) that forks it and waits for it with wait4: the reading's floor is then
the launcher's (measure it with a trivial command, e.g. `quadopt --version`). Used by
tools/bench_scale.py and tools/bench_memory.py.
"""

import os
import subprocess
import sys

# The launcher of the module docs (run by a fresh `python -I -S -c`): starts ARGV[2:], waits for
# it with wait4 and writes its exit code, ru_maxrss (KiB) and wall seconds to the file
# descriptor ARGV[1].
LAUNCHER = r"""
import os, sys, time
fd = int(sys.argv[1])
os.set_inheritable(fd, False)
t0 = time.perf_counter()
pid = os.fork()
if pid == 0:
    try:
        os.execv(sys.argv[2], sys.argv[2:])
    finally:
        os._exit(127)
_, status, usage = os.wait4(pid, 0)
os.write(fd, f"{os.waitstatus_to_exitcode(status)} {usage.ru_maxrss} {time.perf_counter() - t0!r}".encode())
"""


def launch(cmd):
    """Runs cmd through LAUNCHER: (stdout, its peak RSS in KiB, its wall seconds, from fork to
    wait4); a failure raises with its stderr."""
    r, w = os.pipe()
    try:
        p = subprocess.Popen([sys.executable, "-I", "-S", "-c", LAUNCHER, str(w), *cmd],
                             stdout=subprocess.PIPE, stderr=subprocess.PIPE, pass_fds=(w,))
        os.close(w)
        w = None
        out, err = p.communicate()
        with os.fdopen(r, "rb") as f:
            r = None
            fields = f.read().split()
    finally:
        for fd in (r, w):
            if fd is not None:
                os.close(fd)
    if p.returncode != 0 or len(fields) != 3 or int(fields[0]) != 0:
        msg = err.decode(errors="replace").strip() or f"exit code {fields[0].decode() if fields else p.returncode}"
        raise RuntimeError(f"{' '.join(cmd)}: {msg}")
    return out, int(fields[1]), float(fields[2])
