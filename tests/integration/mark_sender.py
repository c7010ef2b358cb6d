# Sends software markers to two agents' --mark-port as a teleoperation stack would: every 10 ms a
# command KEY is marked `cmd` on the operator's board, and 5 ms later `apply` on the vehicle's, for
# SECONDS or until SIGTERM (m2mlat-mark/1, docs/markers.md); prints how many commands it marked. Used
# by the collect breakdown tests.
# usage: mark_sender.py OPERATOR_PORT VEHICLE_PORT SECONDS
import signal
import socket
import sys
import time

operator, vehicle, seconds = int(sys.argv[1]), int(sys.argv[2]), float(sys.argv[3])
s = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
end = time.monotonic() + seconds
stopped = False


def stop(*_):
    global stopped
    stopped = True


signal.signal(signal.SIGTERM, stop)
key = 0
while not stopped and time.monotonic() < end:
    key += 1
    s.sendto(f"m2mlat-mark/1 cmd key={key}".encode(), ("127.0.0.1", operator))
    time.sleep(0.005)
    s.sendto(f"m2mlat-mark/1 apply key={key}".encode(), ("127.0.0.1", vehicle))
    time.sleep(0.005)
print(key)
