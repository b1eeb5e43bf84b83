# CTest script of samples.tg-view-screenshot: renders frames of the demo in a window on a
# virtual X server, then checks the saved PNG (size, more than a flat colour).
# cmake -DXVFB_RUN=... -DVIEW=tg-view -DCHECK=tg-view-png-check -DOUT=shot.png -P ScreenshotTest.cmake
file(REMOVE "${OUT}")
# xvfb-run's default screen is 8 bits deep, which has no visual for an RGB OpenGL context.
execute_process(
  COMMAND "${XVFB_RUN}" -a -s "-screen 0 640x480x24"
          "${VIEW}" --screenshot "${OUT}" --frames 3 --size 160x120
  RESULT_VARIABLE code OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(NOT code EQUAL 0)
  message(FATAL_ERROR "tg-view exited with ${code}\nstdout: ${out}\nstderr: ${err}")
endif()
message(STATUS "${err}")
execute_process(COMMAND "${CHECK}" "${OUT}" 160 120
                RESULT_VARIABLE code OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(NOT code EQUAL 0)
  message(FATAL_ERROR "screenshot check failed: ${out}${err}")
endif()
message(STATUS "${out}")
