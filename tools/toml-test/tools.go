// SPDX-License-Identifier: Apache-2.0

//go:build tools

// Package tools pins the toml-test runner (see go.mod): the blank import
// keeps "go mod tidy" from dropping it.
package tools

import _ "github.com/toml-lang/toml-test/cmd/toml-test"
