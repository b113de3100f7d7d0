"""The REST client against a real HTTP server on 127.0.0.1 that replays the fixtures,
recomputes the HMAC signature of every request from the spec (ONSHAPE.md section 7), and
answers 429 / 401 / 403 / 404 / 500 or stalls when told to."""

from __future__ import annotations

import base64
import hashlib
import hmac
import json
import threading
import time
from email.utils import parsedate_to_datetime
from datetime import datetime, timezone
from http.server import BaseHTTPRequestHandler, ThreadingHTTPServer
from pathlib import Path

import pytest

from ibfem.importers import OnshapeError
from ibfem.importers.onshape import OnshapeClient, load_part, parse_document_url
from test_onshape_support import FIXTURES

pytest.importorskip("requests")

ACCESS, SECRET = "AKtestaccess0123456789", "SKtestsecret-abcdefghijklmnopqrstuvwxyz"
DID, WID, EID, MV = "a" * 24, "b" * 24, "c" * 24, "d" * 24
STUDIO = "half_cylinder_on_block"


class FakeOnshape:
    """Replays one fixture. ``plan[endpoint]`` is a list of answers to give before the real
    one: an int status (429 carries Retry-After: 1) or "stall"."""

    def __init__(self, studio=STUDIO, auth="hmac"):
        self.studio = FIXTURES / studio
        self.auth = auth
        self.plan: dict[str, list] = {}
        self.log: list[dict] = []
        self.nonces: set[str] = set()
        self.stall_seconds = 1.0
        server = self

        class Handler(BaseHTTPRequestHandler):
            def log_message(self, *args):  # quiet
                pass

            def do_GET(self):
                server.handle(self)

        self.httpd = ThreadingHTTPServer(("127.0.0.1", 0), Handler)
        self.httpd.daemon_threads = True
        self.thread = threading.Thread(target=self.httpd.serve_forever, daemon=True)

    @property
    def base(self):
        return f"http://127.0.0.1:{self.httpd.server_address[1]}"

    def url(self, wvm="w", wvmid=WID, query=""):
        return f"{self.base}/documents/{DID}/{wvm}/{wvmid}/e/{EID}" + (f"?{query}" if query else "")

    def check_auth(self, h, path, query) -> bool:
        auth = h.headers.get("Authorization", "")
        if self.auth == "basic":
            return auth == "Basic " + base64.b64encode(f"{ACCESS}:{SECRET}".encode()).decode()
        if not auth.startswith(f"On {ACCESS}:HmacSHA256:"):
            return False
        nonce, date, ctype = h.headers.get("On-Nonce", ""), h.headers.get("Date", ""), h.headers.get("Content-Type", "")
        if len(nonce) < 16 or not nonce.isalnum() or nonce in self.nonces:
            return False
        self.nonces.add(nonce)
        skew = abs((datetime.now(timezone.utc) - parsedate_to_datetime(date)).total_seconds())
        if skew > 300:
            return False
        text = f"get\n{nonce}\n{date}\n{ctype}\n{path}\n{query}\n".lower()
        expected = base64.b64encode(hmac.new(SECRET.encode(), text.encode(), hashlib.sha256).digest()).decode()
        return hmac.compare_digest(auth.split(":")[-1], expected)

    def handle(self, h):
        path, _, query = h.path.partition("?")
        ok = self.check_auth(h, path, query)
        endpoint = path.rsplit("/", 1)[-1]
        redirected = path.startswith("/r/")
        entry = {"path": path, "query": query, "auth_ok": ok, "t": time.monotonic(), "endpoint": endpoint}
        if redirected:
            path = path[2:]
        self.log.append(entry)
        if not ok:
            return self.reply(h, 401, b'{"message":"Unauthenticated API request"}')
        plan = (self.plan.get(endpoint) or []) if not redirected else []
        if plan:
            step = plan.pop(0)
            entry["answer"] = step
            if step == "stall":
                time.sleep(self.stall_seconds)
                return self.reply(h, 200, b"{}")
            if step == "redirect":  # 307 to the same resource under /r: must be re-signed
                return self.reply(h, 307, b"", {"Location": f"/r{h.path}"})
            headers = {"Retry-After": "1"} if step == 429 else {}
            return self.reply(h, step, b'{"message":"planned failure"}', headers)
        if endpoint == "currentmicroversion":
            if path != f"/api/v10/documents/d/{DID}/w/{WID}/currentmicroversion":
                return self.reply(h, 404, b"{}")
            return self.reply(h, 200, json.dumps({"microversion": MV}).encode())
        expected = f"/api/v10/partstudios/d/{DID}/m/{MV}/e/{EID}/{endpoint}"
        if path != expected or endpoint not in ("tessellatedfaces", "tessellatededges", "bodydetails"):
            return self.reply(h, 404, b'{"message":"not found"}')
        return self.reply(h, 200, (self.studio / f"{endpoint}.json").read_bytes())

    @staticmethod
    def reply(h, status, body, headers=None):
        try:
            h.send_response(status)
            h.send_header("Content-Type", "application/json;charset=UTF-8")
            h.send_header("Content-Length", str(len(body)))
            for k, v in (headers or {}).items():
                h.send_header(k, v)
            h.end_headers()
            h.wfile.write(body)
        except (BrokenPipeError, ConnectionResetError):  # the client gave up (timeout test)
            pass

    def __enter__(self):
        self.thread.start()
        return self

    def __exit__(self, *exc):
        self.httpd.shutdown()
        self.httpd.server_close()


def client(**kw):
    opts = dict(access_key=ACCESS, secret_key=SECRET, retry_after_scale=0.05, backoff=0.01, timeout=(2.0, 2.0))
    opts.update(kw)
    return OnshapeClient(**opts)


def _no_key_in(directory: Path):
    basic = base64.b64encode(f"{ACCESS}:{SECRET}".encode()).decode()
    for f in (p for p in directory.rglob("*") if p.is_file()):
        data = f.read_bytes()
        for secret in (ACCESS, SECRET, basic):
            assert secret.encode() not in data, f"{secret[:4]}... found in {f}"


def test_import_with_retries_valid_signatures_and_no_keys_on_disk(tmp_path):
    with FakeOnshape() as srv:
        srv.plan = {"tessellatedfaces": [429, 500], "bodydetails": [503]}
        c = client()
        out = c.fetch(srv.url(), tmp_path / "part")
        log = list(srv.log)
    assert all(e["auth_ok"] for e in log), log
    answers = [e.get("answer") for e in log]
    assert answers.count(429) == 1 and answers.count(500) == 1 and answers.count(503) == 1
    # Retry-After: 1 s honoured (scaled by 0.05 for the test)
    i = next(k for k, e in enumerate(log) if e.get("answer") == 429)
    assert log[i + 1]["t"] - log[i]["t"] >= 0.05
    for name in ("tessellatedfaces.json", "tessellatededges.json", "bodydetails.json"):
        assert (out / name).read_bytes() == (FIXTURES / STUDIO / name).read_bytes()  # exactly as received
    src = json.loads((out / "source.json").read_text())
    assert (src["documentId"], src["elementId"], src["microversion"], src["wvm"]) == (DID, EID, MV, "m")
    assert "fetchedAt" in src and src["url"] == srv.url()
    _no_key_in(tmp_path)
    # the query asked for facet and vertex normals
    q = next(e["query"] for e in log if e["endpoint"] == "tessellatedfaces")
    assert "outputFacetNormals=true" in q and "outputVertexNormals=true" in q
    part = load_part(out)
    assert set(part.faces) == set(load_part(FIXTURES / STUDIO).faces)


def test_a_cached_microversion_is_never_fetched_twice(tmp_path):
    with FakeOnshape() as srv:
        c = client()
        c.fetch(srv.url(), tmp_path / "p")
        first = len(srv.log)
        c.fetch(srv.url(), tmp_path / "p")
        second = srv.log[first:]
    assert first == 4
    assert [e["endpoint"] for e in second] == ["currentmicroversion"]


def test_microversion_urls_need_no_resolution(tmp_path):
    with FakeOnshape() as srv:
        client().fetch(srv.url("m", MV), tmp_path / "p")
        assert [e["endpoint"] for e in srv.log] == ["tessellatedfaces", "tessellatededges", "bodydetails"]


def test_basic_auth(tmp_path):
    with FakeOnshape(auth="basic") as srv:
        client(auth="basic").fetch(srv.url(), tmp_path / "p")
        assert all(e["auth_ok"] for e in srv.log) and len(srv.log) == 4
    _no_key_in(tmp_path)


def test_wrong_keys_give_a_clear_401(tmp_path):
    with FakeOnshape() as srv:
        with pytest.raises(OnshapeError) as info:
            client(secret_key="wrong-secret").fetch(srv.url(), tmp_path / "p")
    msg = str(info.value)
    assert "401" in msg and "ONSHAPE_ACCESS_KEY" in msg and "stack" in msg
    assert "wrong-secret" not in msg and ACCESS not in msg
    assert not (tmp_path / "p").exists()


@pytest.mark.parametrize("status,words", [(403, ["403", "clock"]), (404, ["404", "ids"])])
def test_403_and_404_explain_what_to_check(tmp_path, status, words):
    with FakeOnshape() as srv:
        srv.plan = {"bodydetails": [status]}
        with pytest.raises(OnshapeError) as info:
            client().fetch(srv.url(), tmp_path / "p")
    assert all(w in str(info.value) for w in words)
    assert not (tmp_path / "p").exists()  # nothing half-written


def test_retries_are_bounded(tmp_path):
    with FakeOnshape() as srv:
        srv.plan = {"tessellatedfaces": [500] * 10}
        with pytest.raises(OnshapeError, match="HTTP 500 after 3 attempts"):
            client(max_retries=2).fetch(srv.url(), tmp_path / "p")
        assert sum(1 for e in srv.log if e["endpoint"] == "tessellatedfaces") == 3


def test_a_stalled_server_times_out_then_recovers(tmp_path):
    with FakeOnshape() as srv:
        srv.stall_seconds = 0.6
        srv.plan = {"tessellatededges": ["stall"]}
        t = time.monotonic()
        out = client(timeout=(1.0, 0.2), max_retries=1).fetch(srv.url(), tmp_path / "p")
        assert time.monotonic() - t < 5
        assert (out / "tessellatededges.json").read_bytes() == (FIXTURES / STUDIO / "tessellatededges.json").read_bytes()
        srv.plan = {"tessellatedfaces": ["stall", "stall"]}
        with pytest.raises(OnshapeError, match="timed out after 2 attempts"):
            client(timeout=(1.0, 0.2), max_retries=1).fetch(srv.url(), tmp_path / "q")


def test_missing_keys(monkeypatch, tmp_path):
    monkeypatch.delenv("ONSHAPE_ACCESS_KEY", raising=False)
    monkeypatch.delenv("ONSHAPE_SECRET_KEY", raising=False)
    with pytest.raises(OnshapeError, match="ONSHAPE_ACCESS_KEY and ONSHAPE_SECRET_KEY"):
        OnshapeClient().fetch("https://cad.onshape.com/documents/" + DID + "/w/" + WID + "/e/" + EID, tmp_path)
    assert "SK" not in repr(OnshapeClient(access_key="AK", secret_key="SKsecret"))


def test_cli_import_with_keys_from_the_environment(tmp_path, monkeypatch, capsys):
    from ibfem.solver.cli import main

    monkeypatch.setenv("ONSHAPE_ACCESS_KEY", ACCESS)
    monkeypatch.setenv("ONSHAPE_SECRET_KEY", SECRET)
    with FakeOnshape() as srv:
        assert main(["import", srv.url(), "--out", str(tmp_path / "p")]) == 0
        assert all(e["auth_ok"] for e in srv.log)
        out = capsys.readouterr().out
        assert "imported 2 bodies, 10 faces" in out
        srv.plan = {"bodydetails": [404]}
        assert main(["import", srv.url(), "--out", str(tmp_path / "q")]) == 2
        assert "404" in capsys.readouterr().err
    _no_key_in(tmp_path)


# ---------------------------------------------------------------------------------------
# URLs
# ---------------------------------------------------------------------------------------


def test_document_urls():
    u = parse_document_url(f"https://cad.onshape.com/documents/{DID}/w/{WID}/e/{EID}")
    assert (u.base, u.did, u.wvm, u.wvmid, u.eid, u.configuration) == ("https://cad.onshape.com", DID, "w", WID, EID, "")
    u = parse_document_url(f"https://acme.onshape.com/documents/{DID}/v/{WID}/e/{EID}?configuration=size%3D2%3Bx%3D1")
    assert u.base == "https://acme.onshape.com" and u.wvm == "v" and u.configuration == "size%3D2%3Bx%3D1"
    assert parse_document_url(f"http://127.0.0.1:8080/documents/{DID}/m/{MV}/e/{EID}").base == "http://127.0.0.1:8080"
    with pytest.raises(ValueError, match="plain http"):
        parse_document_url(f"http://cad.onshape.com/documents/{DID}/w/{WID}/e/{EID}")
    with pytest.raises(ValueError, match="path must be"):
        parse_document_url(f"https://cad.onshape.com/documents/{DID}/x/{WID}/e/{EID}")


def test_configuration_is_passed_through_and_signed(tmp_path):
    with FakeOnshape() as srv:
        client().fetch(srv.url(query="configuration=size%3D2"), tmp_path / "p")
        qs = [e["query"] for e in srv.log if e["endpoint"] != "currentmicroversion"]
        assert all(q.startswith("configuration=size%3D2") for q in qs) and all(e["auth_ok"] for e in srv.log)


def test_redirects_are_followed_and_re_signed(tmp_path):
    with FakeOnshape() as srv:
        srv.plan = {"bodydetails": ["redirect"]}
        out = client().fetch(srv.url(), tmp_path / "p")
        paths = [e["path"] for e in srv.log]
    assert any(p.startswith("/r/api/v10/partstudios/") for p in paths)
    assert all(e["auth_ok"] for e in srv.log)
    assert (out / "bodydetails.json").read_bytes() == (FIXTURES / STUDIO / "bodydetails.json").read_bytes()
