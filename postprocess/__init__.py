"""WireNet post-processing: zone forces, VTU export, figures and study reports.

Run ``/usr/bin/python3 -m postprocess --help`` for the command line; see doc/postprocess.md.
"""

__version__ = "1.0"
