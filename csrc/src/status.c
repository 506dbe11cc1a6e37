/*
 * SPDX-FileCopyrightText: 2026 The zwidth authors
 * SPDX-License-Identifier: Apache-2.0
 */

#include "zwidth/status.h"

const char *zw_status_name(zw_status status)
{
    const char *name;
    switch (status) {
    case ZW_OK: name = "ZW_OK"; break;
    case ZW_ERR_NULL: name = "ZW_ERR_NULL"; break;
    case ZW_ERR_NAN: name = "ZW_ERR_NAN"; break;
    case ZW_ERR_INF: name = "ZW_ERR_INF"; break;
    case ZW_ERR_MASS: name = "ZW_ERR_MASS"; break;
    case ZW_ERR_PERIOD: name = "ZW_ERR_PERIOD"; break;
    case ZW_ERR_DAMPING: name = "ZW_ERR_DAMPING"; break;
    case ZW_ERR_DELTA: name = "ZW_ERR_DELTA"; break;
    case ZW_ERR_RANGE: name = "ZW_ERR_RANGE"; break;
    case ZW_ERR_ARG: name = "ZW_ERR_ARG"; break;
    case ZW_ERR_DOMAIN: name = "ZW_ERR_DOMAIN"; break;
    case ZW_ERR_FPENV: name = "ZW_ERR_FPENV"; break;
    case ZW_ERR_DELAY: name = "ZW_ERR_DELAY"; break;
    case ZW_ERR_FILTER: name = "ZW_ERR_FILTER"; break;
    case ZW_ERR_BUSY: name = "ZW_ERR_BUSY"; break;
    case ZW_ERR_BOX: name = "ZW_ERR_BOX"; break;
    default: name = "ZW_UNKNOWN"; break; /* a value outside the enumeration */
    }
    return name;
}
