/*
 * SPDX-FileCopyrightText: 2026 The zwidth authors
 * SPDX-License-Identifier: Apache-2.0
 */

/* zwidth/zwidth.h - the whole firmware core in one include. */
#ifndef ZWIDTH_ZWIDTH_H
#define ZWIDTH_ZWIDTH_H

#include "zwidth/batch.h"
#include "zwidth/box.h"
#include "zwidth/box_cert.h"
#include "zwidth/plant_box.h"
#include "zwidth/coeffs.h"
#include "zwidth/device.h"
#include "zwidth/device_loop.h"
#include "zwidth/extremes.h"
#include "zwidth/ident.h"
#include "zwidth/loop.h"
#include "zwidth/loop_limits.h"
#include "zwidth/margin.h"
#include "zwidth/plant.h"
#include "zwidth/real.h"
#include "zwidth/region.h"
#include "zwidth/regmap.h"
#include "zwidth/selftest.h"
#include "zwidth/status.h"
#include "zwidth/sweep.h"
#include "zwidth/version.h"

#endif /* ZWIDTH_ZWIDTH_H */
