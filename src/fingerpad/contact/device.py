"""Where the contact solver's arrays live: the CPU (NumPy) or a GPU (CuPy, PyTorch).

The solver is written against the Array API standard (docs/solver.md), so its ``xp`` argument
runs it on any compliant namespace. :func:`device_namespace` turns a device name, given or from
the environment variable ``FINGERPAD_DEVICE``, into that namespace: ``"cpu"`` is NumPy (the
default), ``"cupy"`` CuPy on its current CUDA device, ``"torch"`` PyTorch (through
``array_api_compat``) with CUDA tensors. A solver built without ``xp`` asks it, so that
``fingerpad solve``, ``predict`` and the workers of a sweep (which inherit the variable) all
run on the device chosen by ``--device`` or ``FINGERPAD_DEVICE``.

A GPU library that is not installed, or that sees no CUDA device, is a
:class:`~fingerpad.errors.SetupError` naming the setting: a command refuses to start on it
rather than running somewhere else than asked.
"""

from __future__ import annotations

import os
from typing import Any

from ..errors import SetupError

__all__ = ["DEVICES", "choice_setting", "device_namespace", "device_setting"]

#: Device names, in the order they are listed to users.
DEVICES = ("cpu", "cupy", "torch")


def device_setting(device: str | None = None) -> tuple[str, str]:
    """The device asked for and where it came from: ``device``, else ``FINGERPAD_DEVICE``, else
    ``"cpu"`` (any case, surrounding blanks ignored).

    Raises
    ------
    SetupError
        A name that is not one of :data:`DEVICES`.
    """
    return choice_setting(device, "--device", "FINGERPAD_DEVICE", DEVICES, "device")


def choice_setting(value: str | None, option: str, variable: str, choices: tuple[str, ...],
                   what: str) -> tuple[str, str]:
    """``value`` (from ``option``), else the environment ``variable``, else ``choices[0]``:
    lower-cased and checked against ``choices``; returned with where it came from.

    Raises
    ------
    SetupError
        ``unknown {what} ...`` naming the value, its source and the choices.
    """
    source = option
    if value is None:
        value, source = os.environ.get(variable, "") or choices[0], variable
    name = str(value).strip().lower()
    if name not in choices:
        raise SetupError(f"unknown {what} {value!r} ({source}): choose one of {', '.join(choices)}")
    return name, source


def device_namespace(device: str | None = None) -> Any:
    """The array namespace of ``device`` (see :func:`device_setting`): ``None`` for the CPU
    (the solver's NumPy default), the CuPy module, or ``array_api_compat.torch`` with PyTorch's
    default device set to CUDA (the solver creates its arrays with the namespace's own
    constructors, which put them there).

    Raises
    ------
    SetupError
        An unknown name, the library not installed, or no CUDA device visible to it.
    """
    name, source = device_setting(device)
    if name == "cpu":
        return None
    if name == "cupy":
        try:
            import cupy  # noqa: PLC0415 - optional, and seconds to import
        except ImportError:
            raise SetupError(f"device 'cupy' ({source}) needs CuPy, which is not installed "
                             "(pip install cupy-cuda12x, matching the CUDA driver)") from None
        try:
            count = int(cupy.cuda.runtime.getDeviceCount())
        except Exception:  # noqa: BLE001 - CUDARuntimeError without a driver, or a broken one
            count = 0
        if count < 1:
            raise SetupError(f"device 'cupy' ({source}): CuPy sees no CUDA device on this machine")
        return cupy
    try:
        import torch  # noqa: PLC0415 - optional, and seconds to import
    except ImportError:
        raise SetupError(f"device 'torch' ({source}) needs PyTorch, which is not installed") from None
    if not torch.cuda.is_available():
        raise SetupError(f"device 'torch' ({source}): PyTorch sees no CUDA device on this machine")
    from array_api_compat import torch as xtorch  # noqa: PLC0415 - PyTorch's Array API namespace
    # The solver makes its arrays with xp.asarray / xp.full / xp.zeros, which follow this.
    torch.set_default_device("cuda")
    return xtorch
