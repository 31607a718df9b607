# The CTest test rules_decoder_only: configures and builds tests/decoder_only (core + progressive
# + lod alone) in BUILD, then walks DPM's levels with it. Fails when the decoder needs anything
# else to compile or link.
foreach(step "-S;${SOURCE}/tests/decoder_only;-B;${BUILD};-G;Ninja"
             "--build;${BUILD}")
  execute_process(COMMAND ${CMAKE_COMMAND} ${step} RESULT_VARIABLE failed
                  OUTPUT_VARIABLE out ERROR_VARIABLE out)
  if(failed)
    message(FATAL_ERROR "the decoder alone (core + progressive + lod) does not build:\n${out}")
  endif()
endforeach()
execute_process(COMMAND ${BUILD}/dpm_levels ${DPM} RESULT_VARIABLE failed OUTPUT_VARIABLE out
                ERROR_VARIABLE out)
string(REGEX MATCHALL "level [0-9]+: [0-9]+ vertices" levels "${out}")
list(LENGTH levels count)
if(failed OR NOT count EQUAL 11)
  message(FATAL_ERROR "dpm_levels ${DPM} failed:\n${out}")
endif()
message(STATUS "${out}")
