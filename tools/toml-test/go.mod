// SPDX-License-Identifier: Apache-2.0
//
// Pins the runner of toml-test, the official TOML test suite, for
// tools/setup.sh: `go install github.com/toml-lang/toml-test/cmd/toml-test`
// run in this folder builds v1.6.0 with exactly the modules of go.sum.
//
// Why a module of our own rather than `go install ...@v1.6.0`: toml-test
// v1.6.0 requires a pre-release of BurntSushi/toml
// (v1.5.1-0.20250415140922-f225e861e346) that the Go module proxy we reach
// does not serve (it answers 403); requiring the released v1.6.0 here makes
// Go pick that instead. The runner uses that package only to test encoders
// and for its -errors and -cat options, none of which roz's test uses.
module roz/tools/toml-test

go 1.19

require github.com/toml-lang/toml-test v1.6.0

require (
	github.com/BurntSushi/toml v1.6.0 // indirect
	github.com/rivo/uniseg v0.4.7 // indirect
	zgo.at/jfmt v0.0.0-20240726113937-e6436421fade // indirect
	zgo.at/runewidth v0.1.0 // indirect
	zgo.at/termtext v1.5.0 // indirect
	zgo.at/zli v0.0.0-20241220135549-7a37675fadfd // indirect
	zgo.at/zstd v0.0.0-20240531161000-9840c0c39ff5 // indirect
)
