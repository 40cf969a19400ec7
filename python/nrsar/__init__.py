#
# Copyright 2026 gr-nrsar authors.
#
# SPDX-License-Identifier: GPL-3.0-or-later
#

# The presence of this file turns this directory into a Python package

'''
gr-nrsar: SAR imaging inside a UAV's 5G NR uplink data backhaul.

The C++ blocks and kernels (bindings), the shared parameter types and their builders
(params), the options of the imaging chain (options.SimOptions) and the chain itself as a
hier block (imaging_chain); the rooms of the package: docs/architecture.md.
'''

# import pybind11 generated symbols into the nrsar namespace
from .nrsar_python import *

from .params import (make_numerology, make_geometry, make_scene, make_srs, make_dmrs,
                     make_modulation, make_tx_mode, make_filter, make_presum_method,
                     make_presum_domain, make_doppler_band, make_colormap, parse_target,
                     make_trajectory, make_navigation, make_moco_order, make_pusch_config,
                     make_pusch_coding, make_pusch_scrambling, make_autofocus_method)
from .scenes import (make_map, make_beam, load_scene_file, SceneFileError)
from .options import SimOptions, IsacOptions, SoakOptions, OptionError
from .chain import imaging_chain
