#!/usr/bin/python3
# SPDX-License-Identifier: GPL-2.0-or-later
"""Copy a URDF without what the peer check cannot or should not read.

Usage: /usr/bin/python3 bench/urdf/strip_for_peer.py IN.urdf OUT.urdf

Removes <visual> and <collision> (DART fails on meshes it cannot find), <mimic> (DART
keeps mimic joints in its constraint solver, not in its forward dynamics) and <dynamics>
(DART's forward dynamics treats joint damping implicitly, adding the time step times the
damping to the joints' articulated inertia, where mbsc's is the force -c q' of the
continuous equations), so that both tools see the same tree of free, undamped joints.
"""
import sys
import xml.etree.ElementTree as ET

tree = ET.parse(sys.argv[1])
for parent in tree.getroot().iter():
    for child in list(parent):
        if child.tag in ("visual", "collision", "mimic", "dynamics"):
            parent.remove(child)
tree.write(sys.argv[2])
