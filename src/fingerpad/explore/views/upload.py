"""Uploading a measured height map: size-limited while it arrives, stored under a generated name
in the server's upload area (:mod:`..uploads`; the user's file name is never a path).

The page says ``reading NAME ...`` as soon as the file has arrived; the map is read on the next
tick, so the message reaches the browser before the seconds of reading and checking.

The drop zone (Panel's FileDropper, on FilePond) and FilePond's scripts come with the first
choice of *measured map (upload)*, not with the page: once loaded, FilePond runs an animation loop
on every frame whether or not a drop zone exists, which kept Chromium at ~15 % of a core on an
idle page (0.62 s of CPU in 4 s; 0.04 s without it) and slowed every change's drawing.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

import lazy_loader

pn = lazy_loader.load("panel")

from ..uploads import StoredUpload, UploadArea, display_name

__all__ = ["Upload", "bounded_dropper", "script_loader"]

_LOADER_ESM = """
export function render({ model, el }) {
  // scripts and style sheets into the document (in order), once per page; then tell the server
  const load = () => {
    if (!model.scripts.length) return
    if (window.fpLoadedScripts) { model.send_msg({loaded: true}); return }
    for (const href of model.sheets) {
      const link = document.createElement("link")
      link.rel = "stylesheet"
      link.href = href
      document.head.append(link)
    }
    let chain = Promise.resolve()
    for (const src of model.scripts)
      chain = chain.then(() => new Promise((ok, fail) => {
        const script = document.createElement("script")
        script.src = src
        script.onload = ok
        script.onerror = fail
        document.head.append(script)
      }))
    chain.then(() => { window.fpLoadedScripts = true; model.send_msg({loaded: true}) })
  }
  model.on("scripts", load)
  load()
}
"""
_LOADER: Any = None


def script_loader(on_loaded: Callable[[], None]) -> Any:
    """A component that loads the scripts and style sheets put in its ``scripts``/``sheets``
    into the page, then calls ``on_loaded`` (what the page says is only a signal: calling it
    early or twice makes a drop zone that waits for its script, or nothing)."""
    global _LOADER
    if _LOADER is None:
        import param

        class ScriptLoader(pn.custom.JSComponent):
            scripts = param.List(default=[])
            sheets = param.List(default=[])
            _esm = _LOADER_ESM

            def __init__(self, on_loaded: Callable[[], None], **params: Any) -> None:
                super().__init__(**params)
                self._on_loaded = on_loaded

            def _handle_msg(self, msg: Any) -> None:
                if isinstance(msg, dict) and msg.get("loaded") is True:
                    self._on_loaded()

        _LOADER = ScriptLoader
    return _LOADER(on_loaded, height=0, width=0, margin=0)


def bounded_dropper(limit: int, on_start: Callable[[str], None], on_refused: Callable[[str], None],
                    **params: Any) -> Any:
    """A FileDropper that keeps at most ``limit`` bytes of one file in memory while it arrives.

    Panel's FileDropper buffers every chunk a client sends, for any number of names, until the
    client says the last has come: its ``max_file_size`` is checked only in the browser. This one
    refuses, server-side, a file whose chunks pass ``limit`` bytes and more than one file at once.
    """

    class _Dropper(pn.widgets.FileDropper):
        def _process_event(self, event: Any) -> None:
            data = event.data if isinstance(event.data, dict) else {}
            if event.event_name != "upload_event":
                return super()._process_event(event)
            name = str(data.get("name", ""))
            chunk = data.get("chunk")
            if chunk == 1:
                self._file_buffer.clear()  # one file at a time: a new upload drops any other
                on_start(display_name(name))
            elif name not in self._file_buffer:
                return  # a chunk without its start (or after a refusal): ignored
            payload = data.get("data", b"")
            size = len(payload) * (3 / 4 if isinstance(payload, str) else 1)
            held = sum(len(b) for b in self._file_buffer.get(name, []))
            if held + size > limit:
                self._file_buffer.pop(name, None)
                on_refused(f"{display_name(name)}: uploads are limited to {limit / 2**20:.0f} MiB")
                return
            return super()._process_event(event)

    return _Dropper(**params)


class Upload:
    """A drop zone for one measured map; ``on_change(upload, message, reading)`` receives the
    stored file (``None``: none), a message, and whether the map is about to be read."""

    def __init__(self, folder: str, limit: int,
                 on_change: Callable[[StoredUpload | None, str | None, bool], None]) -> None:
        self.area = UploadArea(folder)
        self.limit = limit
        self.on_change = on_change
        self.current: StoredUpload | None = None
        self.dropper: Any = None  # made when first shown, once FilePond is in the page
        self.loader = script_loader(self._make_dropper)
        self.panel = pn.Column(
            pn.pane.HTML(f"<div style='font-size:12px'>measured height map (at most {limit / 2**20:.0f} MiB): "
                         "text, .npy or instrument files</div>"),
            self.loader, sizing_mode="stretch_width", margin=0, visible=False)

    def show(self, visible: bool) -> None:
        """Show or hide the drop zone; the first showing loads FilePond into the page, and the drop
        zone is made once it is there."""
        if visible and not self.loader.scripts:
            from panel.models.file_dropper import FileDropper

            self.loader.param.update(sheets=list(getattr(FileDropper, "__css__", [])),
                                     scripts=list(FileDropper.__javascript__))
        self.panel.visible = visible

    def _make_dropper(self) -> None:
        if self.dropper is not None:
            return
        self.dropper = bounded_dropper(
            self.limit, self._started, self._refused, max_file_size=f"{max(1, self.limit // 2**20)}MB",
            multiple=False, css_classes=["fp-upload"], sizing_mode="stretch_width", layout="compact")
        self.dropper.param.watch(self._changed, "value")
        self.panel.append(self.dropper)

    @property
    def original_name(self) -> str | None:
        return None if self.current is None else self.current.name

    def _started(self, name: str) -> None:
        self.on_change(self.current, f"receiving {name} ...", False)

    def _refused(self, message: str) -> None:
        self.current = None
        self.on_change(None, message, False)

    def _changed(self, event: Any) -> None:
        value = event.new or {}
        if not value:
            self.current = None
            self.on_change(None, None, False)
            return
        name, data = next(iter(value.items()))
        try:
            self.current = self.area.store(name, data, self.limit)
        except ValueError as exc:
            self.current = None
            self.on_change(None, f"{display_name(name)}: {exc}", False)
            return
        finally:
            value.clear()  # the bytes are on disk now: do not keep a second copy in memory
        self.on_change(self.current, f"reading {self.current.name} ...", True)
