# budget_slam_module(NAME <name> SOURCES ... LIBS ...)
#   One library target per module: budget_slam_<name>, alias budget_slam::<name>,
#   public headers in modules/<name>/include/budget_slam/<name>/.
function(budget_slam_module)
  cmake_parse_arguments(M "" "NAME" "SOURCES;LIBS" ${ARGN})
  add_library(budget_slam_${M_NAME} STATIC ${M_SOURCES})
  add_library(budget_slam::${M_NAME} ALIAS budget_slam_${M_NAME})
  target_include_directories(budget_slam_${M_NAME} PUBLIC ${CMAKE_CURRENT_SOURCE_DIR}/include)
  target_link_libraries(budget_slam_${M_NAME} PUBLIC ${M_LIBS})
  target_compile_features(budget_slam_${M_NAME} PUBLIC cxx_std_17)
endfunction()

# budget_slam_test(NAME <name> SOURCES ... LIBS ... [LABELS ...] [TIMEOUT seconds])
#   A GoogleTest executable registered with CTest; BUDGET_SLAM_SOURCE_DIR points tests at
#   rawlogs/ and the public datasets. LABELS go on every test of the executable (`slow`: over
#   20 s; `sanitize`: fast enough to run again under the sanitizers, tools/sanitize.sh).
function(budget_slam_test)
  cmake_parse_arguments(T "" "NAME;TIMEOUT" "SOURCES;LIBS;LABELS" ${ARGN})
  if(NOT BUILD_TESTING)
    return()
  endif()
  add_executable(${T_NAME} ${T_SOURCES})
  set_target_properties(${T_NAME} PROPERTIES RUNTIME_OUTPUT_DIRECTORY ${CMAKE_BINARY_DIR}/tests)
  target_link_libraries(${T_NAME} PRIVATE ${T_LIBS} GTest::gtest GTest::gtest_main)
  target_compile_definitions(${T_NAME} PRIVATE
    BUDGET_SLAM_SOURCE_DIR="${PROJECT_SOURCE_DIR}"
    BUDGET_SLAM_BINARY_DIR="${CMAKE_BINARY_DIR}")
  set(labels "")
  if(T_LABELS)
    set(labels LABELS "${T_LABELS}")
  endif()
  if(T_TIMEOUT)
    list(APPEND labels TIMEOUT ${T_TIMEOUT})
  endif()
  gtest_discover_tests(${T_NAME} DISCOVERY_TIMEOUT 120
    PROPERTIES ENVIRONMENT "BUDGET_SLAM_SOURCE_DIR=${PROJECT_SOURCE_DIR}" ${labels})
endfunction()

# budget_slam_benchmark(NAME <name> SOURCES ... LIBS ...): Google Benchmark executable in bin/.
function(budget_slam_benchmark)
  cmake_parse_arguments(B "" "NAME" "SOURCES;LIBS" ${ARGN})
  if(NOT benchmark_FOUND)
    return()
  endif()
  add_executable(${B_NAME} ${B_SOURCES})
  target_link_libraries(${B_NAME} PRIVATE ${B_LIBS} benchmark::benchmark)
endfunction()
