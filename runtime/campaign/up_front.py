"""The checks of a campaign command that need no campaign folder, made before one exists (so that a
refused ``rpo mc run`` can be run again unchanged): the Dask extra and scheduler of ``--dask``."""

from __future__ import annotations

from rpo.runtime.errors import CampaignError


def check_dask(address: str | None, timeout: float = 5.0) -> None:
    """Refuse ``--dask`` before anything is written: Dask distributed not installed, or a scheduler
    ``address`` (``tcp://host:port``) that does not accept a connection within ``timeout`` [s]."""
    if address is None:
        return
    import importlib.util
    import socket
    from urllib.parse import urlsplit

    if importlib.util.find_spec("distributed") is None:
        raise CampaignError("--dask needs Dask distributed, which is not installed: pip install 'dask[distributed]' "
                            "(or pip install 'rpo[dask]'), then run the command again")
    if address == "local":
        return
    parts = urlsplit(address if "://" in address else f"tcp://{address}")
    try:
        host, port = parts.hostname, parts.port
    except ValueError:
        host, port = None, None
    if not host or not port:
        raise CampaignError(f"--dask {address}: not a scheduler address (host and port, as tcp://10.0.0.5:8786)")
    if parts.scheme not in ("tcp", "tls"):
        return  # another transport (ucx, inproc): Dask itself tells
    try:
        socket.create_connection((host, port), timeout=timeout).close()
    except OSError as exc:
        raise CampaignError(f"--dask {address}: no scheduler answers there ({exc.strerror or exc}): start one "
                            "(dask scheduler) or give its address; nothing was written") from None
