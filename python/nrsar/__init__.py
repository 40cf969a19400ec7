#
# Copyright 2026 gr-nrsar authors.
#
# SPDX-License-Identifier: GPL-3.0-or-later
#

# The presence of this file turns this directory into a Python package

'''
gr-nrsar: SAR imaging inside a UAV's 5G NR uplink data backhaul.

Blocks: nr_isac_tx, scene_echo, tf_filter, range_ifft; shared parameter types
numerology, geometry, scene (see params.py for builders from presets and strings).
'''

# import pybind11 generated symbols into the nrsar namespace
from .nrsar_python import *

from .params import (make_numerology, make_geometry, make_scene, make_srs, make_dmrs,
                     make_modulation, make_tx_mode, make_filter, make_presum_method,
                     make_presum_domain, make_doppler_band, make_colormap, parse_target)
from .scenes import (make_map, make_beam, load_scene_file, SceneFileError)
