class FreeInput_imf
	parameter Real `k` = 2. "k";
	Real `x` "";
	Real `InPutPort1.vo` "";
	input Real `InPutPort1.vi` "";
	Real `OutPutPort1.vi` "";
	output Real `OutPutPort1.vo` "";
equation
	`InPutPort1.vi` = `InPutPort1.vo`;
	der(`x`) = ((- (`k` * `x`)) + `InPutPort1.vo`);
	`OutPutPort1.vi` = `x`;
	`OutPutPort1.vo` = `OutPutPort1.vi`;
end FreeInput_imf;
