"""The annotator's local web server: a starlette app bound to 127.0.0.1 that serves one page, the
location's map image and a small JSON API. Every request is bounded in size, typed by pydantic and
refused when it comes from another site (Host / Origin checks against DNS rebinding and CSRF)."""

from __future__ import annotations

import json
import threading
from importlib import resources
from pathlib import Path
from typing import Any

from pydantic import ValidationError
from starlette.applications import Starlette
from starlette.middleware import Middleware
from starlette.middleware.trustedhost import TrustedHostMiddleware
from starlette.requests import Request
from starlette.responses import HTMLResponse, JSONResponse, Response
from starlette.routing import Route

from socnavgen.annotate import assist
from socnavgen.annotate.models import SavePayload
from socnavgen.annotate.store import AnnotationStore, SaveRejected
from socnavgen.errors import SocnavgenError
from socnavgen.safeio import JSONLimitError, parse_json_text

MAX_BODY_BYTES = 4 * 1024 * 1024  # a full 1296-node graph is ~150 kB
MAX_MAP_UPLOAD_BYTES = 16 * 1024 * 1024
MAP_UPLOAD_TYPES = ("image/png", "image/x-portable-graymap", "image/x-portable-anymap", "application/octet-stream")
LOOPBACK = "127.0.0.1"
STATIC_FILES = {"annotator.js": "text/javascript; charset=utf-8", "annotator.css": "text/css; charset=utf-8"}
SECURITY_HEADERS = {
    "Content-Security-Policy": "default-src 'self'; img-src 'self' blob: data:; object-src 'none'; "
                               "frame-ancestors 'none'; base-uri 'none'",
    "X-Content-Type-Options": "nosniff",
    "Referrer-Policy": "no-referrer",
    "Cache-Control": "no-store",
}


class RequestRefused(Exception):
    def __init__(self, status: int, message: str, problems: list[str] | None = None) -> None:
        super().__init__(message)
        self.status, self.message, self.problems = status, message, problems or []


def _static_text(name: str) -> str:
    return resources.files("socnavgen.annotate").joinpath("static", name).read_text(encoding="utf-8")


def _error(status: int, message: str, problems: list[str] | None = None) -> JSONResponse:
    return JSONResponse({"error": message, "problems": problems or []}, status_code=status,
                        headers=SECURITY_HEADERS)


async def read_json_body(request: Request, limit: int = MAX_BODY_BYTES) -> Any:
    """The request body as JSON, refusing non-JSON, cross-site and oversized requests before parsing."""
    data = await read_body(request, ("application/json",), limit)
    try:
        return parse_json_text(data.decode("utf-8"))  # depth and integer limits: never a RecursionError
    except JSONLimitError as exc:
        raise RequestRefused(413, f"body refused: {exc}") from exc
    except (UnicodeDecodeError, json.JSONDecodeError) as exc:
        raise RequestRefused(400, f"body is not valid JSON: {exc}") from exc


async def read_body(request: Request, content_types: tuple[str, ...], limit: int) -> bytes:
    """The raw body, only from this page's origin, of an allowed type, and at most `limit` bytes."""
    origin = request.headers.get("origin")
    host = request.headers.get("host", "")
    if origin is not None and origin not in (f"http://{host}", f"https://{host}"):
        raise RequestRefused(403, f"request from another site ({origin}) refused")
    if request.headers.get("content-type", "").split(";")[0].strip().lower() not in content_types:
        raise RequestRefused(415, f"send the body as {' or '.join(content_types)}")
    declared = request.headers.get("content-length")
    if declared is not None and (not declared.isdigit() or int(declared) > limit):
        raise RequestRefused(413, f"request body larger than {limit} bytes")
    chunks, size = [], 0
    async for chunk in request.stream():
        size += len(chunk)
        if size > limit:
            raise RequestRefused(413, f"request body larger than {limit} bytes")
        chunks.append(chunk)
    return b"".join(chunks)


def parse_payload(data: Any) -> SavePayload:
    try:
        return SavePayload.model_validate(data)
    except ValidationError as exc:
        problems = [f"{'.'.join(str(p) for p in e['loc']) or 'body'}: {e['msg']}" for e in exc.errors()[:50]]
        raise RequestRefused(422, "the graph does not have the expected shape", problems) from exc


def create_app(location_dir: Path | str) -> Starlette:
    """The annotator app for one location folder (loaded now, so a broken folder fails early)."""
    store = AnnotationStore(location_dir)

    async def index(request: Request) -> Response:
        return HTMLResponse(_static_text("index.html"), headers=SECURITY_HEADERS)

    async def static(request: Request) -> Response:
        name = request.path_params["name"]
        if name not in STATIC_FILES:  # a fixed list: no path is ever built from the request
            return _error(404, "not found")
        return Response(_static_text(name), media_type=STATIC_FILES[name], headers=SECURITY_HEADERS)

    async def location(request: Request) -> Response:
        return JSONResponse({**store.state(), **assist.page_extras(store)}, headers=SECURITY_HEADERS)

    async def suggest(request: Request) -> Response:
        payload = parse_payload(await read_json_body(request))  # the page's current schema, to extend
        result = assist.suggest_graph(store, payload.schema_.node_types, payload.schema_.edge_types)
        return JSONResponse(result, headers=SECURITY_HEADERS)

    async def guess_type(request: Request) -> Response:
        data = await read_json_body(request, limit=64 * 1024)
        try:
            x, y = float(data["x"]), float(data["y"])
            types = [str(t) for t in data["node_types"]][:64]
        except (KeyError, TypeError, ValueError) as exc:
            raise RequestRefused(422, "send {x, y, node_types}") from exc
        return JSONResponse({"type": assist.guess_node_type(store, x, y, types)}, headers=SECURITY_HEADERS)

    async def description(request: Request) -> Response:
        data = await read_json_body(request, limit=64 * 1024)
        if not isinstance(data, dict) or not isinstance(data.get("description"), str):
            raise RequestRefused(422, "send {description: text}")
        try:
            return JSONResponse(assist.save_description(store, data["description"]), headers=SECURITY_HEADERS)
        except SaveRejected as exc:
            return _error(422, "description not saved", exc.problems)

    async def map_image(request: Request) -> Response:
        if request.method == "POST":
            data = await read_body(request, MAP_UPLOAD_TYPES, MAX_MAP_UPLOAD_BYTES)
            try:
                return JSONResponse(store.replace_map(data), headers=SECURITY_HEADERS)
            except SaveRejected as exc:
                return _error(422, "map not replaced", exc.problems)
        return Response(store.map_png(), media_type="image/png", headers=SECURITY_HEADERS)

    async def save(request: Request) -> Response:
        payload = parse_payload(await read_json_body(request))
        try:
            result = store.save(payload)
        except SaveRejected as exc:
            return _error(422, "not saved: the graph breaks the schema", exc.problems)
        except (OSError, SocnavgenError) as exc:  # rendering or disk: the previous files are untouched
            return _error(500, f"not saved: {exc}")
        return JSONResponse(result, headers=SECURITY_HEADERS)

    async def check(request: Request) -> Response:
        if request.method == "GET":
            return JSONResponse({"warnings": store.warnings()}, headers=SECURITY_HEADERS)
        payload = parse_payload(await read_json_body(request))
        try:
            graph, schema = store.validate(payload)
        except SaveRejected as exc:
            return JSONResponse({"warnings": [{"message": p, "severity": "error", "nodes": [], "edge": None}
                                              for p in exc.problems]}, headers=SECURITY_HEADERS)
        return JSONResponse({"warnings": store.warnings(graph, schema)}, headers=SECURITY_HEADERS)

    async def refused(request: Request, exc: Exception) -> Response:
        assert isinstance(exc, RequestRefused)
        return _error(exc.status, exc.message, exc.problems)

    async def user_error(request: Request, exc: Exception) -> Response:
        return _error(500, exc.render() if isinstance(exc, SocnavgenError) else str(exc))

    routes = [
        Route("/", index),
        Route("/static/{name}", static),
        Route("/api/location", location),
        Route("/api/map", map_image, methods=["GET", "POST"]),
        Route("/api/save", save, methods=["POST"]),
        Route("/api/check", check, methods=["GET", "POST"]),
        Route("/api/suggest", suggest, methods=["POST"]),
        Route("/api/guess-type", guess_type, methods=["POST"]),
        Route("/api/description", description, methods=["POST"]),
    ]
    app = Starlette(
        routes=routes,
        middleware=[Middleware(TrustedHostMiddleware, allowed_hosts=[LOOPBACK, "localhost"])],
        exception_handlers={RequestRefused: refused, SocnavgenError: user_error},
    )
    app.state.store = store
    return app


def make_server(app: Starlette, port: int):  # -> uvicorn.Server
    """A uvicorn server on the loopback interface only (never 0.0.0.0)."""
    import uvicorn

    config = uvicorn.Config(app, host=LOOPBACK, port=port, log_level="warning", access_log=False)
    return uvicorn.Server(config)


def serve_in_thread(app: Starlette, port: int) -> tuple[Any, threading.Thread]:
    """Start the server in a daemon thread (used by tests); returns (server, thread) once it listens."""
    server = make_server(app, port)
    thread = threading.Thread(target=server.run, daemon=True)
    thread.start()
    import time

    deadline = time.monotonic() + 10
    while not server.started:
        if not thread.is_alive() or time.monotonic() > deadline:
            raise RuntimeError(f"annotator server did not start on {LOOPBACK}:{port}")
        time.sleep(0.02)
    return server, thread
