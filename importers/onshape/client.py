"""Onshape REST client: document URLs, API-key authentication (HMAC request signing or HTTP
Basic), timeouts, bounded retries, and the on-disk cache (one directory per part studio).

Only these endpoints are called:

* ``GET /api/{v}/documents/d/{did}/w/{wid}/currentmicroversion`` (resolve a workspace to an
  immutable microversion, so the cache is keyed by it);
* ``GET /api/{v}/partstudios/d/{did}/m/{mid}/e/{eid}/{tessellatedfaces|tessellatededges|bodydetails}``
  or, for one part, ``/api/{v}/parts/d/{did}/m/{mid}/e/{eid}/partid/{pid}/...``.

The three responses are written byte for byte as received, plus ``source.json`` (URL, ids,
microversion, tolerances, time of fetch: never a key). A directory already holding the same
document/element/part/configuration at the same microversion is not fetched again.

Retries are hand-written rather than delegated to ``urllib3.Retry`` because every HMAC
attempt must be signed afresh (new nonce and date): 429 waits ``Retry-After`` seconds (times
``retry_after_scale``, at most ``max_retry_after``), 5xx and network errors back off
exponentially; at most ``max_retries`` retries. ``requests`` is imported lazily.
"""

from __future__ import annotations

import base64
import email.utils
import hashlib
import hmac
import json
import logging
import os
import re
import secrets
import string
import time
from dataclasses import dataclass, field
from datetime import datetime, timezone
from pathlib import Path
from typing import Any
from urllib.parse import quote, urlsplit

from .. import OnshapeError

__all__ = ["DocumentUrl", "parse_document_url", "OnshapeClient", "sign_hmac", "LOOPBACK_HOSTS"]

log = logging.getLogger(__name__)

LOOPBACK_HOSTS = ("127.0.0.1", "localhost", "::1")
ACCEPT = "application/json;charset=UTF-8; qs=0.09"
CONTENT_TYPE = "application/json"
_PATH = re.compile(r"^(?:/[^/]+)*?/documents/(?P<did>\w+)/(?P<wvm>[wvm])/(?P<wvmid>\w+)/e/(?P<eid>\w+)/?$")
_NONCE_CHARS = string.ascii_letters + string.digits
FILES = ("tessellatedfaces.json", "tessellatededges.json", "bodydetails.json")


@dataclass(frozen=True)
class DocumentUrl:
    """A parsed Onshape document URL: ``scheme://host/documents/{did}/{w|v|m}/{id}/e/{eid}``."""

    base: str  # scheme://host[:port], the API host (enterprise stacks differ)
    did: str
    wvm: str
    wvmid: str
    eid: str
    configuration: str = ""  # passed through unchanged (already URL-encoded)
    url: str = ""


def parse_document_url(url: str) -> DocumentUrl:
    """Parse a document URL; https only, except plain http to a loopback host (tests)."""
    if not isinstance(url, str) or not url.strip():
        raise ValueError(f"document URL must be a non-empty string, got {url!r}")
    parts = urlsplit(url.strip())
    host = parts.hostname or ""
    if parts.scheme not in ("https", "http") or not host:
        raise ValueError(f"document URL {url!r}: expected https://<host>/documents/<did>/<w|v|m>/<id>/e/<eid>")
    if parts.scheme == "http" and host not in LOOPBACK_HOSTS:
        raise ValueError(f"document URL {url!r}: plain http is only accepted for a loopback host "
                         f"({', '.join(LOOPBACK_HOSTS)}); use https")
    m = _PATH.match(parts.path)
    if not m:
        raise ValueError(f"document URL {url!r}: path must be /documents/<did>/<w|v|m>/<id>/e/<eid>, "
                         f"got {parts.path!r}")
    configuration = ""
    for item in parts.query.split("&") if parts.query else ():
        key, _, value = item.partition("=")
        if key == "configuration":
            configuration = value
    return DocumentUrl(base=f"{parts.scheme}://{parts.netloc}", did=m["did"], wvm=m["wvm"], wvmid=m["wvmid"],
                       eid=m["eid"], configuration=configuration, url=url.strip())


def sign_hmac(secret_key: str, method: str, nonce: str, date: str, content_type: str, path: str, query: str) -> str:
    """base64(HMAC-SHA256(secret, lower(method\\nnonce\\ndate\\ncontent-type\\npath\\nquery\\n)))."""
    text = f"{method}\n{nonce}\n{date}\n{content_type}\n{path}\n{query}\n".lower()
    digest = hmac.new(secret_key.encode("utf-8"), text.encode("utf-8"), hashlib.sha256).digest()
    return base64.b64encode(digest).decode("ascii")


def _segment(value: str) -> str:
    return quote(value, safe="")  # '/' -> %2F, '+' -> %2B in path segments


@dataclass
class OnshapeClient:
    """Fetch and cache tessellated faces, tessellated edges and body details.

    Keys come from the arguments or from ``ONSHAPE_ACCESS_KEY`` / ``ONSHAPE_SECRET_KEY``.
    ``auth`` is ``"hmac"`` (default, request signing) or ``"basic"``. ``timeout`` is the
    (connect, read) timeout in seconds. ``retry_after_scale`` multiplies server
    ``Retry-After`` values (1.0 in use; tests make it small so whole-second values stay fast).
    """

    access_key: str | None = None
    secret_key: str | None = field(default=None, repr=False)
    auth: str = "hmac"
    api_version: str | None = "v10"
    timeout: tuple[float, float] | float = (10.0, 60.0)
    max_retries: int = 4
    backoff: float = 0.5
    max_backoff: float = 30.0
    max_retry_after: float = 120.0
    retry_after_scale: float = 1.0
    chord_tolerance: float | None = None
    angle_tolerance: float | None = None
    max_facet_width: float | None = None
    session: Any = field(default=None, repr=False)
    requests_made: int = field(default=0, init=False)

    def __post_init__(self) -> None:
        self.access_key = self.access_key or os.environ.get("ONSHAPE_ACCESS_KEY")
        self.secret_key = self.secret_key or os.environ.get("ONSHAPE_SECRET_KEY")
        if self.auth not in ("hmac", "basic"):
            raise ValueError(f"auth must be 'hmac' or 'basic', got {self.auth!r}")
        if self.max_retries < 0:
            raise ValueError(f"max_retries must be >= 0, got {self.max_retries!r}")
        for name in ("chord_tolerance", "angle_tolerance", "max_facet_width"):
            v = getattr(self, name)
            if v is not None and not (isinstance(v, (int, float)) and v > 0):
                raise ValueError(f"{name} must be a positive number, got {v!r}")
        if self.angle_tolerance is not None and self.angle_tolerance >= 1.5707963267948966:
            raise ValueError(f"angle_tolerance must be below pi/2 radians, got {self.angle_tolerance!r}")

    def __repr__(self) -> str:  # never show the keys
        return f"OnshapeClient(auth={self.auth!r}, api_version={self.api_version!r}, keys={'set' if self.access_key else 'missing'})"

    # -- HTTP ---------------------------------------------------------------------------

    def _check_keys(self) -> None:
        if not self.access_key or not self.secret_key:
            raise OnshapeError("no Onshape API keys: set ONSHAPE_ACCESS_KEY and ONSHAPE_SECRET_KEY "
                               "(or pass access_key/secret_key)")

    def _headers(self, method: str, path: str, query: str) -> dict[str, str]:
        headers = {"Accept": ACCEPT, "Content-Type": CONTENT_TYPE}
        if self.auth == "basic":
            token = base64.b64encode(f"{self.access_key}:{self.secret_key}".encode()).decode("ascii")
            headers["Authorization"] = f"Basic {token}"
            return headers
        nonce = "".join(secrets.choice(_NONCE_CHARS) for _ in range(25))
        date = email.utils.formatdate(usegmt=True)
        sig = sign_hmac(self.secret_key, method, nonce, date, CONTENT_TYPE, path, query)
        headers.update({"Date": date, "On-Nonce": nonce, "Authorization": f"On {self.access_key}:HmacSHA256:{sig}"})
        return headers

    def _session_(self):
        if self.session is None:
            try:
                import requests  # lazy: optional dependency (pip install ibfem[onshape])
            except ImportError:  # pragma: no cover
                raise OnshapeError("the Onshape client needs 'requests': pip install 'ibfem[onshape]'") from None
            self.session = requests.Session()
        return self.session

    def _api(self, base: str, path: str) -> str:
        return f"/api/{self.api_version}{path}" if self.api_version else f"/api{path}"

    def get(self, base: str, path: str, query: str = "") -> bytes:
        """GET ``base + path?query`` with authentication and retries; the raw body."""
        self._check_keys()
        import requests

        session = self._session_()
        attempt = 0
        redirects = 0
        while True:
            url = base + path + (f"?{query}" if query else "")
            headers = self._headers("GET", path, query)
            self.requests_made += 1
            log.debug("GET %s (attempt %d)", path, attempt + 1)
            try:
                resp = session.get(url, headers=headers, timeout=self.timeout, allow_redirects=False)
            except (requests.Timeout, requests.ConnectionError) as exc:
                kind = "timed out" if isinstance(exc, requests.Timeout) else "connection failed"
                if attempt >= self.max_retries:
                    raise OnshapeError(f"GET {path}: {kind} after {attempt + 1} attempts "
                                       f"(timeout {self.timeout} s)") from None
                self._sleep(self._backoff(attempt))
                attempt += 1
                continue
            status = resp.status_code
            if status in (301, 302, 303, 307, 308) and "Location" in resp.headers:
                redirects += 1
                if redirects > 5:
                    raise OnshapeError(f"GET {path}: too many redirects")
                loc = urlsplit(requests.compat.urljoin(url, resp.headers["Location"]))
                base, path, query = f"{loc.scheme}://{loc.netloc}", loc.path, loc.query  # re-signed next round
                continue
            if status == 200:
                return resp.content
            if status == 429 or status >= 500:
                if attempt >= self.max_retries:
                    raise OnshapeError(f"GET {path}: HTTP {status} after {attempt + 1} attempts"
                                       + (" (rate limited: wait and try again)" if status == 429 else
                                          " (Onshape server error)"))
                wait = self._retry_after(resp.headers.get("Retry-After")) if status == 429 else None
                self._sleep(wait if wait is not None else self._backoff(attempt))
                attempt += 1
                continue
            raise OnshapeError(self._explain(status, base, path, resp))

    def _backoff(self, attempt: int) -> float:
        return min(self.max_backoff, self.backoff * 2.0**attempt)

    def _retry_after(self, value: str | None) -> float | None:
        if value is None:
            return None
        value = value.strip()
        try:
            seconds = float(value)
        except ValueError:
            try:  # HTTP-date form
                when = email.utils.parsedate_to_datetime(value)
                seconds = (when - datetime.now(timezone.utc)).total_seconds()
            except (TypeError, ValueError):
                return None
        return min(self.max_retry_after, max(0.0, seconds)) * self.retry_after_scale

    @staticmethod
    def _sleep(seconds: float) -> None:
        time.sleep(max(0.0, seconds))

    def _explain(self, status: int, base: str, path: str, resp: Any) -> str:
        host = urlsplit(base).hostname
        if status == 401:
            return (f"GET {path}: HTTP 401 Unauthorized: the API keys were not accepted by {host}; check "
                    f"ONSHAPE_ACCESS_KEY/ONSHAPE_SECRET_KEY and that the keys belong to this stack "
                    f"(keys from cad.onshape.com do not work on an enterprise stack and vice versa)")
        if status == 403:
            hint = " With HMAC signing also check the computer's clock: the Date header must be within " \
                   "5 minutes of Onshape's." if self.auth == "hmac" else ""
            return (f"GET {path}: HTTP 403 Forbidden: the keys have no read access to this document "
                    f"(not shared with the key's owner, or the key lacks the read scope).{hint}")
        if status == 404:
            return (f"GET {path}: HTTP 404 Not Found: check the document, workspace/version/microversion, "
                    f"element and part ids in the URL (or the document is not shared with you)")
        body = resp.text[:200] if getattr(resp, "text", None) else ""
        return f"GET {path}: HTTP {status}: {body}".rstrip(": ")

    # -- endpoints ------------------------------------------------------------------------

    def current_microversion(self, doc: DocumentUrl) -> str:
        """The workspace's current microversion id (immutable: the cache key)."""
        if doc.wvm != "w":
            raise ValueError("current_microversion needs a workspace (w) URL")
        path = self._api(doc.base, f"/documents/d/{_segment(doc.did)}/w/{_segment(doc.wvmid)}/currentmicroversion")
        body = self.get(doc.base, path)
        try:
            data = json.loads(body)
        except json.JSONDecodeError:
            raise OnshapeError(f"GET {path}: the answer is not JSON") from None
        mv = data.get("microversion") or data.get("microversionId") or data.get("id") if isinstance(data, dict) else None
        if isinstance(mv, dict):
            mv = mv.get("theId")
        if not isinstance(mv, str) or not re.fullmatch(r"\w+", mv):
            raise OnshapeError(f"GET {path}: no microversion id in the answer")
        return mv

    def _query(self, doc: DocumentUrl, what: str, part_id: str | None) -> str:
        q: list[tuple[str, str]] = []
        if doc.configuration:
            q.append(("configuration", doc.configuration))
        if what == "tessellatedfaces":
            q += [("outputFacetNormals", "true"), ("outputVertexNormals", "true")]
            if self.max_facet_width is not None:
                q.append(("maxFacetWidth", repr(float(self.max_facet_width))))
        if what in ("tessellatedfaces", "tessellatededges"):
            if self.chord_tolerance is not None:
                q.append(("chordTolerance", repr(float(self.chord_tolerance))))
            if self.angle_tolerance is not None:
                q.append(("angleTolerance", repr(float(self.angle_tolerance))))
        if what == "bodydetails":
            q.append(("includeGeometricData", "true"))
        return "&".join(f"{k}={v if k == 'configuration' else quote(v, safe='')}" for k, v in q)

    def endpoint_path(self, doc: DocumentUrl, what: str, wvm: str, wvmid: str, part_id: str | None = None) -> str:
        ids = f"/d/{_segment(doc.did)}/{wvm}/{_segment(wvmid)}/e/{_segment(doc.eid)}"
        if part_id:
            return self._api(doc.base, f"/parts{ids}/partid/{_segment(part_id)}/{what}")
        return self._api(doc.base, f"/partstudios{ids}/{what}")

    def fetch(self, url: str, out: str | Path, part_id: str | None = None, force: bool = False) -> Path:
        """Fetch the part studio (or one part) of ``url`` into the directory ``out``.

        Workspaces are resolved to their current microversion first; when ``out`` already
        holds that microversion (same ids, configuration and tolerances) nothing else is
        fetched. Returns ``out``.
        """
        doc = parse_document_url(url)
        out = Path(out)
        self._check_keys()
        if doc.wvm == "w":
            wvm, wvmid = "m", self.current_microversion(doc)
            microversion = wvmid
        else:
            wvm, wvmid = doc.wvm, doc.wvmid
            microversion = doc.wvmid if doc.wvm == "m" else None
        source = {
            "url": doc.url, "host": urlsplit(doc.base).hostname, "documentId": doc.did,
            "workspaceId": doc.wvmid if doc.wvm == "w" else None, "wvm": wvm, "wvmId": wvmid,
            "elementId": doc.eid, "partId": part_id, "configuration": doc.configuration,
            "microversion": microversion, "versionId": doc.wvmid if doc.wvm == "v" else None,
            "tolerances": {"chordTolerance": self.chord_tolerance, "angleTolerance": self.angle_tolerance,
                           "maxFacetWidth": self.max_facet_width},
            "options": {"outputFacetNormals": True, "outputVertexNormals": True, "outputIndexTable": False},
            "apiVersion": self.api_version, "auth": self.auth,
        }
        if not force and self._cached(out, source):
            log.info("%s: microversion %s already cached", out, wvmid)
            return out
        bodies = {}
        for name in FILES:
            what = name[:-5]
            path = self.endpoint_path(doc, what, wvm, wvmid, part_id)
            bodies[name] = self.get(doc.base, path, self._query(doc, what, part_id))
        out.mkdir(parents=True, exist_ok=True)
        for name, body in bodies.items():
            (out / name).write_bytes(body)  # exactly as received
        if microversion is None:
            try:  # a version: the body details carry the microversion id
                mv = json.loads(bodies["bodydetails.json"]).get("microversionId")
                source["microversion"] = mv.get("theId") if isinstance(mv, dict) else None
            except (ValueError, AttributeError):
                pass
        source["fetchedAt"] = datetime.now(timezone.utc).strftime("%Y-%m-%dT%H:%M:%SZ")
        (out / "source.json").write_text(json.dumps(source, indent=2) + "\n", encoding="utf-8")
        return out

    @staticmethod
    def _cached(out: Path, source: dict) -> bool:
        try:
            old = json.loads((out / "source.json").read_text(encoding="utf-8"))
        except (OSError, ValueError):
            return False
        if not all((out / n).is_file() for n in FILES):
            return False
        keys = ("host", "documentId", "elementId", "partId", "configuration", "wvm", "wvmId", "tolerances")
        return isinstance(old, dict) and all(old.get(k) == source.get(k) for k in keys) and \
            old.get("wvm") in ("m", "v")
