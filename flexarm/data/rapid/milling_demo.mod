MODULE Milling
    ! flexarm example: a milling-style program for the demo arm (not from the thesis).
    ! A spindle 150 mm out of the flange points down at a workpiece 500 mm above the base;
    ! Line is one straight 300 mm pass, Pocket a pass with a 20 mm corner arc and a second
    ! pass at right angles.  Used by the compensation guide and tests with a constant
    ! tool-frame cutting force.
    PERS tooldata tSpindle:=[TRUE,[[0,0,150],[1,0,0,0]],[20,[0,0,75],[1,0,0,0],0,0,0]];
    CONST robtarget mill_10:=[[1100,-150,500],[0,0,1,0],[-1,0,-1,0],[9E+09,9E+09,9E+09,9E+09,9E+09,9E+09]];
    CONST robtarget mill_20:=[[1400,-150,500],[0,0,1,0],[-1,0,-1,0],[9E+09,9E+09,9E+09,9E+09,9E+09,9E+09]];
    CONST robtarget mill_30:=[[1150,-100,500],[0,0,1,0],[-1,0,-1,0],[9E+09,9E+09,9E+09,9E+09,9E+09,9E+09]];
    CONST robtarget mill_40:=[[1350,-100,500],[0,0,1,0],[-1,0,-1,0],[9E+09,9E+09,9E+09,9E+09,9E+09,9E+09]];
    CONST robtarget mill_50:=[[1364.142,-94.142,500],[0,0,1,0],[-1,0,-1,0],[9E+09,9E+09,9E+09,9E+09,9E+09,9E+09]];
    CONST robtarget mill_60:=[[1370,-80,500],[0,0,1,0],[-1,0,-1,0],[9E+09,9E+09,9E+09,9E+09,9E+09,9E+09]];
    CONST robtarget mill_70:=[[1370,100,500],[0,0,1,0],[0,0,0,0],[9E+09,9E+09,9E+09,9E+09,9E+09,9E+09]];
    PROC Line()
        MoveJ mill_10,v100,fine,tSpindle\WObj:=wobj0;
        MoveL mill_20,v20,fine,tSpindle\WObj:=wobj0;
    ENDPROC
    PROC Pocket()
        MoveJ mill_30,v100,fine,tSpindle\WObj:=wobj0;
        MoveL mill_40,v20,z1,tSpindle\WObj:=wobj0;
        MoveC mill_50,mill_60,v20,z1,tSpindle\WObj:=wobj0;
        MoveL mill_70,v20,fine,tSpindle\WObj:=wobj0;
    ENDPROC
ENDMODULE
