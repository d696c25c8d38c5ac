// An example of the MSL's Electrical.Machines, unchanged (needs Modelica 3.2.2
// on the library path): an asynchronous induction machine with squirrel cage,
// started direct on line at t = 0.1 s through a delta terminal box, driving a
// quadratic load chosen so that it settles at the machine's nominal point
// (TLoad = 161.4 N.m at wLoad = 1440.45 rpm, the example's own parameters).
model AimcDol
  extends Modelica.Electrical.Machines.Examples.AsynchronousInductionMachines.AIMC_DOL;
end AimcDol;
