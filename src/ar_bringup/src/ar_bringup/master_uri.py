"""Whether ROS_MASTER_URI points inside the local network ranges (ROS 1's master has no
authentication: a master reachable from outside the rig's network is open to anyone there).
Used by scripts/check_master_uri, which rig.launch runs at start."""
import socket
from urllib.parse import urlparse

from ar_bringup.rig_check import is_local_address

RANGES = "loopback 127.0.0.0/8 and ::1, RFC 1918 10/8, 172.16/12, 192.168/16, link-local 169.254/16 and fe80::/10"


def warning(uri, resolve=socket.gethostbyname):
    """None when the master's host is local; else one line naming the URI and what to do. A host name
    is resolved with `resolve` (injected in tests); one that does not resolve is named too."""
    if not uri:
        return "ROS_MASTER_URI is not set"
    host = urlparse(uri).hostname
    if not host:
        return "ROS_MASTER_URI '%s' has no host" % uri
    local = is_local_address(host)
    address = host
    if local is None:
        try:
            address = resolve(host)
        except OSError as e:
            return "ROS_MASTER_URI %s: host '%s' does not resolve (%s)" % (uri, host, e)
        local = is_local_address(address)
    if local:
        return None
    return ("ROS_MASTER_URI %s points to %s, outside the local network ranges (%s). ROS 1's master has no "
            "authentication: keep it on the rig's own network (README.md, Rig and base station: security)"
            % (uri, address if address == host else "%s (%s)" % (host, address), RANGES))
