"""zwidth: the exact stability region of impedance-controlled haptic devices and drives.

Python side of zwidth.  Today it holds one module:

    zwidth.modbus   client for the drive-side gain register map (Modbus TCP, pymodbus)

Import submodules explicitly (``from zwidth.modbus import Drive``); this package file
imports nothing, so ``import zwidth`` stays cheap (compiled bindings come later).
"""

__all__ = ["__version__"]

__version__ = "0.1.0"
