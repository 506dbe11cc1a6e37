/*
 * SPDX-FileCopyrightText: 2026 The zwidth authors
 * SPDX-License-Identifier: Apache-2.0
 */

/* zwidth/version.h - the release of zwidth, defined here and nowhere else.
 *
 * Here because the firmware part is also built without CMake (tools/firmware_release.sh,
 * the amalgamation, vendored copies), so the one header every build sees is the one place.
 * CMake's project(VERSION) (hence the pkg-config and CMake package files), the Python
 * package's metadata (scikit-build-core reads the three numbers with a regex, pyproject.toml),
 * zwidth.__version__ and every program's --version come from these three lines;
 * tests/py/test_version.py checks that they agree.  Semantic versioning; CHANGELOG.md. */
#ifndef ZWIDTH_VERSION_H
#define ZWIDTH_VERSION_H

#define ZW_VERSION_MAJOR 0
#define ZW_VERSION_MINOR 1
#define ZW_VERSION_PATCH 0

#define ZW_VERSION_STR_(x) #x
#define ZW_VERSION_XSTR_(x) ZW_VERSION_STR_(x)
/* "MAJOR.MINOR.PATCH", a string literal. */
#define ZW_VERSION_STRING                                                                    \
    ZW_VERSION_XSTR_(ZW_VERSION_MAJOR) "." ZW_VERSION_XSTR_(ZW_VERSION_MINOR) "."           \
        ZW_VERSION_XSTR_(ZW_VERSION_PATCH)

#endif /* ZWIDTH_VERSION_H */
