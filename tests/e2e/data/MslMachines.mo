// An example of the MSL's Electrical.Machines, unchanged (needs Modelica 3.2.2
// on the library path): an asynchronous induction machine with squirrel cage,
// started direct on line at t = 0.1 s through a delta terminal box, driving a
// quadratic load chosen so that it settles at the machine's nominal point
// (TLoad = 161.4 N.m at wLoad = 1440.45 rpm, the example's own parameters).
model AimcDol
  extends Modelica.Electrical.Machines.Examples.AsynchronousInductionMachines.AIMC_DOL;
end AimcDol;

// The same machine fed by a voltage-frequency controlled inverter through a
// grounded star, its own terminals in star with the star point open: the
// frequency ramps to 50 Hz in 1 s, then the nominal load torque 161.4 N.m
// steps in at 1.2 s. The open star point and the zero-sequence inductor make
// the structural choice of dummy derivatives numerically singular.
model AimcInverter
  extends Modelica.Electrical.Machines.Examples.AsynchronousInductionMachines.AIMC_Inverter;
  output Real tau = aimc.tauElectrical "air-gap torque";
  output Real i0 = aimc.i_0_s "stator zero-sequence current";
end AimcInverter;

// A three-phase transformer (vector group Yy00, its connection letters taken
// from `VectorGroup` by Strings.substring when flattening) feeding a
// resistive load.
model TransformerTestbench
  extends Modelica.Electrical.Machines.Examples.Transformers.TransformerTestbench;
  output Real power1 = transformer.powerBalance.power1 "into the primary";
  output Real power2 = transformer.powerBalance.power2 "into the secondary";
  output Real loss = transformer.powerBalance.lossPowerTotal "copper losses";
end TransformerTestbench;

// Two permanent-magnet DC machines started by an armature voltage ramp, one
// without losses and one with friction, core, stray-load and brush losses
// (speed- and current-dependent powers (w/w0)^p), each driving a quadratic
// load sized for its own nominal point (100 A at 1425 rpm, and at 1417.5 rpm
// with losses).
model DcpmWithLosses
  extends Modelica.Electrical.Machines.Examples.DCMachines.DCPM_withLosses;
  output Real ia1 = dcpm1.ia, ia2 = dcpm2.ia;
end DcpmWithLosses;

// The induction machine started in steady state at synchronous speed
// (initial equations der(aimc.idq_sr) = der(aimc.idq_rr) = zeros(2): currents
// the model does not differentiate), then loaded with the nominal torque at
// 0.5 s.
model AimcInitialize
  extends Modelica.Electrical.Machines.Examples.AsynchronousInductionMachines.AIMC_Initialize;
  output Real tau = aimc.tauElectrical "air-gap torque";
end AimcInitialize;

// A permanent-magnet DC machine with its thermal port used: the machine's
// own ambient (`thermalAmbient ... if not useThermalPort`, redeclared by the
// machine) is switched off, and the armature temperature follows an
// exponential from 20 degC to 80 degC, its reference temperature, after the
// load step.
model DcpmTemperature
  extends Modelica.Electrical.Machines.Examples.DCMachines.DCPM_Temperature;
end DcpmTemperature;

// An inverter-fed induction machine driving a conveyor (a mass against the
// regularised sign force of the nominal load) forwards, then backwards, by
// a periodic duty cycle: the load force's derivative overflows at speed.
model AimcConveyor
  extends Modelica.Electrical.Machines.Examples.AsynchronousInductionMachines.AIMC_Conveyor;
end AimcConveyor;

// A 12-pulse rectifier: a three-phase source feeds two diode bridges through
// a Dy1 and a Dd0 transformer (30 degrees apart); both bridges charge the DC
// capacitors and a 0.2 Ohm load in parallel. The ideal diodes' `off = s < 0`
// are relations inside the bridges' algebraic loops.
model Rectifier12pulse
  extends Modelica.Electrical.Machines.Examples.Transformers.Rectifier12pulse;
  output Real vLoad = load.v "DC voltage";
end Rectifier12pulse;

// An electrically excited synchronous generator, speed-ramped to 1500 rpm,
// its terminal voltage held at 100 V by a PI controller of the excitation;
// a nominal load (Z = 1 Ohm per phase, power factor 0.8) is switched on at
// 2 s and dumped at 4 s through a closer with arc, and again at 6 and 8 s.
// Output on the experiment's 1 ms grid: the switch's quench tests sit at 0
// up to rounding while the machine is at rest.
model SmeeLoadDump
  extends Modelica.Electrical.Machines.Examples.SynchronousInductionMachines.SMEE_LoadDump;
  output Real V = voltageQuasiRMSSensor.V "terminal voltage (RMS)";
  output Real I = currentQuasiRMSSensor.I "load current (RMS)";
  output Real tau = smee.tauElectrical "air-gap torque";
  output Real ie = smee.ie "excitation current";
end SmeeLoadDump;

// Two of the MSL's PowerConverters examples: a single-phase thyristor bridge
// fired at 30 degrees into a 20 Ohm load, and a three-phase diode bridge into
// a resistor, each measured by the MSL's Mean and RootMeanSquare blocks
// (sample() ticks one period after t0, a parameter the initial equations set).
model ThyristorBridge2PulseR
  extends Modelica.Electrical.PowerConverters.Examples.ACDC.RectifierBridge2Pulse.ThyristorBridge2Pulse_R;
  output Real vMean = meanVoltage.y, vRms = rootMeanSquareVoltage.y, iMean = meanCurrent.y;
end ThyristorBridge2PulseR;
model DiodeBridge2mPulse
  extends Modelica.Electrical.PowerConverters.Examples.ACDC.RectifierBridge2mPulse.DiodeBridge2mPulse;
  output Real vMean = meanVoltage.y;
end DiodeBridge2mPulse;
