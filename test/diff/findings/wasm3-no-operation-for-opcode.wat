;; SPDX-License-Identifier: Apache-2.0
;; Finding of the long differential run (fuzz/diff/long_run.sh, smith stage;
;; 3 of 40 wasm-tools smith 1.263.0 modules, MVP + bulk memory), partly
;; minimised (line deletion, 1224 -> 591 lines): roz's validator accepts
;; this module (wasm-validate does too), but wasm3 refuses to compile it:
;; "no operation found for opcode" (m3_CompileModule). A controller roz
;; accepts must load; either roz's validator should refuse what wasm3 cannot
;; compile, or wasm3 lacks an operation (every opcode here also appears in
;; modules wasm3 compiles, so likely an opcode in a context, e.g. dead code
;; after br or a loop with a result).
;; Run: wat2wasm this.wat -o s.wasm && build/test/diff/roz_wasm_run s.wasm
;;      (prints "wasm3-refused: no operation found for opcode", exit 3)
(module
  (type (;0;) (func (param i64) (result i64)))
  (type (;1;) (func (param i64)))
  (type (;2;) (func (result i32)))
  (type (;3;) (func (result i64)))
  (type (;4;) (func (result f32)))
  (type (;5;) (func (result f64)))
  (type (;6;) (func))
  (func (;0;) (type 0) (param i64) (result i64)
    (local i32 f64 f64)
    global.get 6
    f32.const 0x1.4770fp-53 (;=1.42005e-16;)
    global.get 1
    global.get 1
    i64.rotl
    i32.const 2147483647
    f32.convert_i32_u
    f64.const 0x1.0860a788eb4a8p-659 (;=4.31735e-199;)
    i32.trunc_f64_s
    f32.const 0x1.12273ap+113 (;=1.1121e+34;)
    f64.promote_f32
    i64.reinterpret_f64
    global.get 1
    i32.wrap_i64
    local.get 1
    i64.extend_i32_u
    i32.const 4194304
    call 2
    f64.const 0x1.ff8p-1065 (;=5.05429e-321;)
    i64.trunc_sat_f64_s
    f64.convert_i64_u
    f64.const nan (;=nan;)
    local.get 2
    local.get 2
    f64.eq
    select
    i32.trunc_sat_f64_s
    i64.const 36028797018963967
    f32.const -0x1.41f4a2p+0 (;=-1.25764;)
    i32.const -34806533
    if (result i32)  ;; label = @1
      i64.const 1048576
      call 5
      block (result i32)  ;; label = @2
        global.get 1
        loop  ;; label = @3
          global.get 6
          if  ;; label = @4
          end
          loop (result f32)  ;; label = @4
            global.get 6
            if  ;; label = @5
            end
            global.get 6
            i32.const 1
            i32.sub
            global.set 6
            call 3
            loop (result f64)  ;; label = @5
              global.get 6
              if  ;; label = @6
              end
              global.get 6
              br 1 (;@4;)
              block (result i64)  ;; label = @6
                f32.const -0x1.d2b21cp+47 (;=-2.56569e+14;)
                i32.trunc_sat_f32_u
                i64.extend_i32_s
                block (result f32)  ;; label = @7
                  loop  ;; label = @8
                    global.get 6
                    br 3 (;@5;)
                  end
                  f32.const -0x1.fffffep+126 (;=-1.70141e+38;)
                end
                i32.reinterpret_f32
                global.get 3
                i32.xor
                global.set 3
              end
              global.set 4
            end
            i64.reinterpret_f64
            global.get 2
            i64.xor
            global.set 2
            global.set 4
            f32.const 0x1.3764c2p+79 (;=7.35257e+23;)
          end
          i32.reinterpret_f32
          global.set 3
        end
        global.set 4
        i32.const -268435457
      end
      global.get 5
      i32.xor
      global.set 5
      i64.reinterpret_f64
      global.get 2
      i64.xor
      global.set 2
      global.set 4
      i32.const 524288
    else
      i32.const 4194303
    end
    global.get 5
    i32.xor
    global.set 5
    i32.reinterpret_f32
    global.get 3
    i32.xor
    global.set 3
    global.set 4
    global.get 5
    i32.xor
    global.set 5
    i32.xor
    global.set 5
    global.set 4
    global.get 5
    i32.xor
    global.set 5
    global.set 4
    global.get 5
    i32.xor
    global.set 5
    i32.reinterpret_f32
    global.get 3
    i32.xor
    global.set 3
    global.set 4
    i32.reinterpret_f32
    i32.xor
    global.set 5
    i64.const -9007199254740992)
  (func (;1;) (type 1) (param i64)
    (local i64 f64)
    local.get 1
    i64.eqz
    f64.convert_i32_u
    i64.trunc_f64_u
    i32.const -1160403035
    i64.const -562949953421313
    f32.const 0x1.p-132 (;=1.83671e-40;)
    i64.const 5835069320330516933
    i32.const -1812721746
    global.set 5
    global.get 4
    i64.xor
    global.set 4
    i32.reinterpret_f32
    global.get 3
    i32.xor
    global.set 3
    global.set 4
    global.get 5
    i32.xor
    global.set 5
    global.set 4)
  (func (;2;) (type 2) (result i32)
    (local i64 i32 f32 f32 f64 f64 f32 f32 f32 f32)
    global.get 6
    if  ;; label = @1
    end
    global.get 0
    i32.trunc_sat_f64_u
    call 3
    local.get 4
    i32.const -1718829383
    f32.convert_i32_s
    i64.const -137438953473
    f32.convert_i64_s
    block (result f64)  ;; label = @1
      block (result f64)  ;; label = @2
        i64.const 2817995963203047021
        block (result i64)  ;; label = @3
          block  ;; label = @4
            call 4
            f32.const nan (;=nan;)
            local.get 7
            local.get 7
            f32.eq
            i64.const -36028797018963969
            br 1 (;@3;)
          end
          i64.const -16
        end
        i64.xor
        global.set 4
        f64.const -nan:0xffdffffffffff (;=-nan;)
      end
    end
    i64.reinterpret_f64
    global.set 2
    i32.reinterpret_f32
    global.set 3
    i32.reinterpret_f32
    global.set 3
    i64.reinterpret_f64
    i64.xor
    global.set 4)
  (func (;3;) (type 3) (result i64)
    (local f32 i64 f64 f32 f64)
    global.get 6
    f32.convert_i32_s
    i32.const 128
    i64.extend_i32_s
    local.get 0
    i32.const 878277458
    call 3
    f64.convert_i64_u
    i32.trunc_sat_f64_s
    local.get 0
    f32.const nan (;=nan;)
    local.get 3
    local.get 3
    f32.eq
    select
    i64.const 8529771765842352132
    f32.convert_i64_s
    block  ;; label = @1
      f64.const 0x1.cde9ed1f907dcp+37 (;=2.47988e+11;)
      loop  ;; label = @2
        global.get 6
        global.set 6
      end
      f64.const nan (;=nan;)
      local.get 4
      local.get 4
      f64.eq
      select
      i64.reinterpret_f64
      global.set 2
    end
    i32.reinterpret_f32
    global.get 3
    i32.xor
    global.set 3
    i32.reinterpret_f32
    global.get 3
    i32.xor
    global.set 3
    i32.xor
    global.set 5
    i32.reinterpret_f32
    global.get 3
    i32.xor
    global.set 3
    global.set 4
    i32.reinterpret_f32
    global.set 3
    i64.const -6172829789516789825)
  (func (;4;) (type 4) (result f32)
    (local f32 f64 f64 f64 f64 f32 f32)
    global.get 6
    if  ;; label = @1
    end
    f64.const 0x1.62aba591146cdp+803 (;=7.39046e+241;)
    i32.const -500185973
    f64.convert_i32_s
    f64.eq
    f32.reinterpret_i32
    br 0 (;@0;)
    if (result f64)  ;; label = @1
      block  ;; label = @2
        loop (result i32)  ;; label = @3
          global.get 6
          if  ;; label = @4
          end
          block (result i64)  ;; label = @4
            i32.const 16843009
            f64.const -nan:0xff80000000000 (;=-nan;)
            i64.trunc_sat_f64_u
            f32.convert_i64_u
            f32.const nan (;=nan;)
            local.get 0
            local.get 0
            f32.eq
            select
            i64.trunc_sat_f32_u
            f64.reinterpret_i64
            f64.const nan (;=nan;)
            local.get 2
            local.get 2
            f64.eq
            select
            i32.trunc_sat_f64_u
            f32.reinterpret_i32
            i64.trunc_sat_f32_u
            f64.const 0x1.8b53d363852c8p+912 (;=5.34654e+274;)
            f64.const nan (;=nan;)
            local.get 3
            local.get 3
            f64.eq
            select
            f32.const 0x1.ce7f0ep-102 (;=3.56294e-31;)
            global.get 0
            i32.trunc_f64_s
            i32.const -1930115930
            i32.ne
            block (result i64)  ;; label = @5
              loop (result f64)  ;; label = @6
                global.get 6
                if  ;; label = @7
                end
                global.get 6
                i32.const 1
                i32.sub
                global.set 6
                loop (result f32)  ;; label = @7
                  block  ;; label = @8
                    f64.const 0x1.58b4f8e9f35cfp+650 (;=6.29082e+195;)
                    i32.const -2019534238
                    br_table 0 (;@8;) 1 (;@7;) 2 (;@6;) 5 (;@3;) 6 (;@2;) 2 (;@6;)
                    f32.sub
                    i32.reinterpret_f32
                    global.set 3
                  end
                  f32.const -0x1.5d5308p-66 (;=-1.84931e-20;)
                end
                i32.reinterpret_f32
                global.set 3
                f64.const 0x1.p-1045 (;=2.65249e-315;)
              end
              i64.reinterpret_f64
            end
            global.get 4
            i64.xor
            global.set 4
            global.set 5
            i32.reinterpret_f32
            global.set 3
            i64.reinterpret_f64
            i64.xor
            global.set 4
            global.set 5
            i64.const 1221916978023506816
          end
          global.get 4
          i64.xor
          global.set 4
          i32.const 286331153
        end
        global.set 5
      end
      f64.const 0x1.ffffp-1058 (;=6.47577e-319;)
    else
      f64.const -0x1.46e7030afde7p+1015 (;=-4.48357e+305;)
    end
    i64.reinterpret_f64
    global.set 2)
  (func (;5;) (type 5) (result f64)
    (local f64 f32 f32 f32 f32 f32 f32)
    global.get 6
    if  ;; label = @1
    end
    global.get 6
    global.set 6
    f32.const 0x1.acb4dep+34 (;=2.877e+10;)
    block (result f64)  ;; label = @1
      f64.const -inf (;=-inf;)
      f64.const nan (;=nan;)
      local.get 0
      local.get 0
      f64.eq
      select
      i32.trunc_sat_f64_u
      i32.const 223030698
      f32.convert_i32_u
      f32.const nan (;=nan;)
      local.get 1
      local.get 1
      f32.eq
      select
      call 5
      call 5
      f32.const -0x1.04631p+84 (;=-1.96743e+25;)
      f32.const nan (;=nan;)
      local.get 2
      local.get 2
      f32.eq
      select
      f32.const nan (;=nan;)
      local.get 3
      local.get 3
      f32.eq
      select
      i64.trunc_sat_f32_s
      block  ;; label = @2
        block (result i64)  ;; label = @3
          i64.const 18014398509481983
          global.get 1
          i32.const -1059725652
          f32.convert_i32_u
          f32.const nan (;=nan;)
          local.get 5
          local.get 5
          f32.eq
          select
          f32.const nan (;=nan;)
          local.get 6
          local.get 6
          f32.eq
          select
          i32.reinterpret_f32
          loop  ;; label = @4
            global.get 6
            if  ;; label = @5
            end
            call 3
            block  ;; label = @5
            end
            f64.reinterpret_i64
            i64.trunc_f64_s
            f32.convert_i64_u
            i32.const -2049
            i32.const -318106118
            if (result f32)  ;; label = @5
              br 3 (;@2;)
              block  ;; label = @6
                block (result i64)  ;; label = @7
                  f32.const 0x1.fffffep-112 (;=3.85186e-34;)
                  i64.trunc_sat_f32_u
                end
                global.set 4
              end
            else
              f32.const -0x1.7f8078p+41 (;=-3.29426e+12;)
            end
            i32.reinterpret_f32
            i32.xor
            global.set 5
            i32.reinterpret_f32
            global.get 3
            i32.xor
            global.set 3
          end
          global.get 5
          i32.xor
          global.set 5
          global.set 4
        end
        global.set 4
      end
      global.set 4
      i64.reinterpret_f64
      global.set 2
      i64.reinterpret_f64
      global.set 2
      i32.reinterpret_f32
      i32.xor
      global.set 5
      f64.const -0x1.552f4c25ecd57p-143 (;=-1.19525e-43;)
    end
    i64.reinterpret_f64
    global.get 2
    i64.xor
    global.set 2
    i32.reinterpret_f32
    global.get 3
    i32.xor
    global.set 3
    f64.const 0x1.dc9270727ed0ep+808 (;=3.17779e+243;))
  (func (;6;) (type 6)
    (local f64 f32 f64 f32 f32 f32 f32 f64 f32)
    loop (result f64)  ;; label = @1
      global.get 6
      f32.const 0x1.9031cap+25 (;=5.24543e+07;)
      i64.const 89204553590663228
      br 0 (;@1;)
      loop  ;; label = @2
        global.get 6
        if  ;; label = @3
        end
        global.get 1
        i64.eqz
        if (result i64)  ;; label = @3
          f64.const -0x1.a2164a84c4463p+951 (;=-3.10851e+286;)
          f64.const nan (;=nan;)
          local.get 2
          local.get 2
          f64.eq
          select
          loop  ;; label = @4
            global.get 6
            if  ;; label = @5
            end
            global.get 6
            i32.const 1
            i32.sub
            global.set 6
            block  ;; label = @5
              loop  ;; label = @6
              end
              f32.const 0x1.8d01b8p+58 (;=4.4699e+17;)
              f32.const nan (;=nan;)
              local.get 3
              local.get 3
              f32.eq
              select
              f32.const nan (;=nan;)
              local.get 4
              local.get 4
              f32.eq
              select
              block  ;; label = @6
                f64.const -0x1.fffffffffffffp+1008 (;=-5.48612e+303;)
                f32.const 0x1.fep-142 (;=3.57331e-43;)
                i32.trunc_f32_u
                i64.extend_i32_s
                f32.const -0x1.cbf472p+90 (;=-2.22421e+27;)
                f32.const nan (;=nan;)
                local.get 5
                local.get 5
                f32.eq
                select
                f32.const nan (;=nan;)
                local.get 6
                local.get 6
                f32.eq
                select
                i32.trunc_sat_f32_s
                f64.const -0x1.4cedcb93de9a4p-374 (;=-3.37982e-113;)
                f64.const nan (;=nan;)
                local.get 7
                local.get 7
                f64.eq
                select
                call 4
                f32.const nan (;=nan;)
                local.get 8
                local.get 8
                f32.eq
                select
                f32.const 0x1.baca76p-53 (;=1.9203e-16;)
                f32.copysign
                global.get 0
                f32.const 0x1.740c66p+77 (;=2.19619e+23;)
                i32.reinterpret_f32
                global.get 3
                i32.xor
                global.set 3
                i64.reinterpret_f64
                global.get 2
                i64.xor
                global.set 2
                i32.reinterpret_f32
                global.get 3
                i32.xor
                global.set 3
                i64.reinterpret_f64
                global.get 2
                i64.xor
                global.set 2
                global.set 5
                global.get 4
                i64.xor
                global.set 4
                i64.reinterpret_f64
                global.get 2
                i64.xor
                global.set 2
              end
              i32.reinterpret_f32
              global.set 3
            end
          end
          i64.reinterpret_f64
        else
          i64.const -3883035493766633770
        end
        global.get 4
        i64.xor
        global.set 4
      end
    end
    i64.reinterpret_f64
    global.get 2
    i64.xor
    global.set 2)
  (global (;0;) f64 (f64.const -0x1.8fd74e0043bc6p-912 (;=-4.51119e-275;)))
  (global (;1;) i64 (i64.const -8622442317899341237))
  (global (;2;) (mut i64) (i64.const 0))
  (global (;3;) (mut i32) (i32.const 0))
  (global (;4;) (mut i64) (i64.const 0))
  (global (;5;) (mut i32) (i32.const 0))
  (global (;6;) (mut i32) (i32.const 100))
  (export "process" (func 1))
  (export "e_void" (func 6)))
