"""Run a command on a pseudo-terminal and press Ctrl-C once a file exists (or after a delay), as a
user at a terminal would: the terminal sends SIGINT to the whole foreground process group.
usage: pty_interrupt.py WAIT_FOR_FILE|- DELAY_S COMMAND...  (prints the output, exits with the
command's exit status; 124 if it did not end within 120 s)"""
import os
import pty
import select
import sys
import time

wait_for, delay, cmd = sys.argv[1], float(sys.argv[2]), sys.argv[3:]
pid, fd = pty.fork()
if pid == 0:
    os.execvp(cmd[0], cmd)
out, t0, ready_at, sent = b"", time.time(), None, False
while time.time() - t0 < 120:
    r, _, _ = select.select([fd], [], [], 0.05)
    if r:
        try:
            data = os.read(fd, 4096)
        except OSError:  # the terminal closed: the command ended
            break
        if not data:
            break
        out += data
    if ready_at is None and (wait_for == "-" or os.path.exists(wait_for)):
        ready_at = time.time()
    if not sent and ready_at is not None and time.time() - ready_at >= delay:
        os.write(fd, b"\x03")  # Ctrl-C: the line discipline signals the foreground group
        sent = True
else:
    os.kill(pid, 9)
    sys.stdout.write(out.decode(errors="replace"))
    sys.exit(124)
_, status = os.waitpid(pid, 0)
sys.stdout.write(out.decode(errors="replace"))
sys.exit(os.waitstatus_to_exitcode(status) if os.waitstatus_to_exitcode(status) >= 0 else 128 - os.waitstatus_to_exitcode(status))
