// 'stream' is a prefix of connector components only (MLS 15.1).
model StreamOutsideConnector
  model Volume
    stream Real h;
  equation
    h = 1;
  end Volume;
  Volume v;
end StreamOutsideConnector;
