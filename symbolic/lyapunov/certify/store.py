"""Where certificates live: one gzipped JSON file per certified statement in ``docs/certificates/``, written
atomically and byte-reproducibly (fixed gzip timestamp), read back with a one-line error when damaged."""

from __future__ import annotations

import gzip
import json
import os
from pathlib import Path

from .recheck import CheckError

ROOT = Path(__file__).resolve().parents[3]
#: The committed certificates: the checkout's docs/certificates.  An installed copy (pip install .) has no
#: docs/: RPO_CERTIFICATES names the folder (tests/conftest.py points it at the checkout running the tests).
STORE = Path(os.environ.get("RPO_CERTIFICATES") or ROOT / "docs" / "certificates")


def path_for(claim_id: str, tag: str, store: Path = STORE) -> Path:
    """``<claim id>.<paper|corrected>.json.gz``: a claim may have a certificate for each statement."""
    return store / f"{claim_id}.{tag}.json.gz"


def write(data: dict, store: Path = STORE) -> Path:
    store.mkdir(parents=True, exist_ok=True)
    path = path_for(data["claim"], data["statement"], store)
    raw = (json.dumps(data, indent=1, sort_keys=True) + "\n").encode()
    tmp = path.with_name(path.name + f".tmp{os.getpid()}")
    with open(tmp, "wb") as fh, gzip.GzipFile(fileobj=fh, mode="wb", mtime=0, filename="") as gz:
        gz.write(raw)
    os.replace(tmp, path)
    return path


def read(claim_id: str, tag: str, store: Path = STORE) -> dict | None:
    path = path_for(claim_id, tag, store)
    if not path.exists():
        return None
    try:
        return json.loads(gzip.decompress(path.read_bytes()))
    except (OSError, ValueError) as exc:
        raise CheckError(f"{path.name} is not a certificate ({exc})") from exc
