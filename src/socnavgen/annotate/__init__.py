"""The browser map annotator: a loopback-only starlette server (server.py), the validated save of a
location folder (store.py, models.py), bridges to `location check` and the renderer (bridge.py), and
a plain HTML/JS/CSS page (static/) with no build step."""
