"""homesim: a deterministic simulator of BIRON's home tour.

The kernel (this package) knows nothing of BIRON: it provides virtual time,
the XML message bus, the hardened XML parser, the trace, the world and the
scenario loader. BIRON lives in ``robot/``, the scripted people in ``humans/``.
"""

__version__ = "0.1.0"
