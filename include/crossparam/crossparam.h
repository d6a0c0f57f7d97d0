// SPDX-License-Identifier: GPL-3.0-or-later
// crossparam: every public header at once (the layout, the map, compatible remeshing, many models, blending,
// transfer, verification, morphing, reading and validation). Include single headers instead to compile less.
#ifndef CROSSPARAM_CROSSPARAM_H
#define CROSSPARAM_CROSSPARAM_H

#include <crossparam/attribute_transfer.h>
#include <crossparam/blending.h>
#include <crossparam/certificate.h>
#include <crossparam/compatible_remeshing.h>
#include <crossparam/cross_parameterization.h>
#include <crossparam/errors.h>
#include <crossparam/io.h>
#include <crossparam/layout_types.h>
#include <crossparam/layout_verification.h>
#include <crossparam/metrics.h>
#include <crossparam/morph.h>
#include <crossparam/multi_remeshing.h>
#include <crossparam/parameters.h>
#include <crossparam/patch_layout.h>
#include <crossparam/remeshing_verification.h>
#include <crossparam/scaling.h>
#include <crossparam/smoothing.h>
#include <crossparam/textured_obj.h>
#include <crossparam/types.h>
#include <crossparam/validation.h>

#endif // CROSSPARAM_CROSSPARAM_H
