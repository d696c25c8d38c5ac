model DiodeThermalLoopStarted
  "DiodeThermalLoop with guesses from which Newton on the whole block starts
   (a thermal voltage of 25 mV at 300 K): the reference for its tearing"
  extends DiodeThermalLoop(Td(start = 300), vt(start = 0.02585));
end DiodeThermalLoopStarted;
