MODULE Module1
    ! flexarm test case: the RAPID module of appendix B of the source thesis
    ! ("Robot Studio Code for Quasi-Static Testing", TRITA-ITM-EX 2019:160, pp. 92-93).
    ! Repaired here (PDF text-extraction damage only): the module was extracted as two
    ! run-on lines; statements are put back one per line with RobotStudio indentation,
    ! the page footer/header text between the two lines ("Page 94: ...", "93 | Appendix B:
    ! ...") is removed, and the comment banner split across the page break is rejoined.
    ! This ten-line note is ours. Every name, number, argument and the
    ! order of declarations and instructions are exactly as printed (9E+09 included).
    ! The RobotStudio template lines "! Description:" / "<Insert description here>" do
    ! not appear in the print and are not restored.
    CONST robtarget Target_50:=[[883.561,-287.318,583.49],[0.707106781,0,0.707106781,0],[-1,-1,0,1],[9E+09,9E+09,9E+09,9E+09,9E+09,9E+09]];
    CONST robtarget Target_20:=[[1037.38,-144.255,583.49],[0.707106781,0,0.707106781,0],[-1,-1,0,1],[9E+09,9E+09,9E+09,9E+09,9E+09,9E+09]];
    CONST robtarget Target_60:=[[882.84,22.68,583.24],[0.707106781,0,0.707106781,0],[0,0,-1,1],[9E+09,9E+09,9E+09,9E+09,9E+09,9E+09]];
    CONST robtarget Target_40:=[[882.84,-127.639,738.419],[0.707106781,0,0.707106781,0],[-1,-1,0,1],[9E+09,9E+09,9E+09,9E+09,9E+09,9E+09]];
    CONST robtarget Target_70:=[[1488.34,47.78,588.13],[0.5,0.5,0.5,-0.5],[0,1,-1,1],[9E+09,9E+09,9E+09,9E+09,9E+09,9E+09]];
    CONST robtarget Target_80:=[[1333.34,202.78,588.13],[0.5,0.5,0.5,-0.5],[0,1,-1,1],[9E+09,9E+09,9E+09,9E+09,9E+09,9E+09]];
    CONST robtarget Target_90:=[[1178.34,47.78,588.13],[0.5,0.5,0.5,-0.5],[0,1,-1,1],[9E+09,9E+09,9E+09,9E+09,9E+09,9E+09]];
    CONST robtarget Target_100:=[[1333.34,-107.22,588.13],[0.5,0.5,0.5,-0.5],[0,1,-1,1],[9E+09,9E+09,9E+09,9E+09,9E+09,9E+09]];
    CONST robtarget Target_110:=[[1488.34,47.78,588.13],[0.5,0.5,0.5,-0.5],[0,1,-1,1],[9E+09,9E+09,9E+09,9E+09,9E+09,9E+09]];
    CONST robtarget Target_120:=[[1451.767,47.78,688.13],[0.5,0.5,0.5,-0.5],[0,1,-1,1],[9E+09,9E+09,9E+09,9E+09,9E+09,9E+09]];
    CONST robtarget Target_130:=[[1331.633,166.195,688.13],[0.5,0.5,0.5,-0.5],[0,1,-1,1],[9E+09,9E+09,9E+09,9E+09,9E+09,9E+09]];
    CONST robtarget Target_140:=[[1214.962,44.367,688.13],[0.5,0.5,0.5,-0.5],[0,1,-1,1],[9E+09,9E+09,9E+09,9E+09,9E+09,9E+09]];
    CONST robtarget Target_150:=[[1335.047,-70.635,688.13],[0.5,0.5,0.5,-0.5],[0,1,-1,1],[9E+09,9E+09,9E+09,9E+09,9E+09,9E+09]];
    CONST robtarget Target_160:=[[1451.767,47.78,688.13],[0.5,0.5,0.5,-0.5],[0,1,-1,1],[9E+09,9E+09,9E+09,9E+09,9E+09,9E+09]];
    CONST robtarget Target_170:=[[1476.256,47.78,648.13],[0.5,0.5,0.5,-0.5],[0,1,-1,1],[9E+09,9E+09,9E+09,9E+09,9E+09,9E+09]];
    CONST robtarget Target_180:=[[1331.454,190.684,648.13],[0.5,0.5,0.5,-0.5],[0,1,-1,1],[9E+09,9E+09,9E+09,9E+09,9E+09,9E+09]];
    CONST robtarget Target_190:=[[1190.474,44.007,648.13],[0.5,0.5,0.5,-0.5],[0,1,-1,1],[9E+09,9E+09,9E+09,9E+09,9E+09,9E+09]];
    CONST robtarget Target_200:=[[1335.226,-95.124,648.13],[0.5,0.5,0.5,-0.5],[0,1,-1,1],[9E+09,9E+09,9E+09,9E+09,9E+09,9E+09]];
    CONST robtarget Target_210:=[[1476.256,47.78,648.13],[0.5,0.5,0.5,-0.5],[0,1,-1,1],[9E+09,9E+09,9E+09,9E+09,9E+09,9E+09]];
    CONST robtarget Target_220:=[[1451.767,47.78,688.13],[0,-0.707106781,0.707106781,0],[0,0,0,0],[9E+09,9E+09,9E+09,9E+09,9E+09,9E+09]];
    CONST robtarget Target_230:=[[1331.633410479,-70.634702977,688.13],[0,0.007205425,0.999974041,0],[0,0,0,0],[9E+09,9E+09,9E+09,9E+09,9E+09,9E+09]];
    CONST robtarget Target_240:=[[1214.962185537,51.192824631,688.13],[0,0.717223104,0.696843612,0],[0,0,0,0],[9E+09,9E+09,9E+09,9E+09,9E+09,9E+09]];
    CONST robtarget Target_250:=[[1335.046589521,166.194702977,688.13],[0,0.999974041,-0.007205425,0],[0,0,0,0],[9E+09,9E+09,9E+09,9E+09,9E+09,9E+09]];
    CONST robtarget Target_260:=[[1451.767,47.78,688.13],[0,-0.707106781,0.707106781,0],[0,0,0,0],[9E+09,9E+09,9E+09,9E+09,9E+09,9E+09]];
    CONST jointtarget calib_post:=[[0,0,0,0,0,0],[0,0,0,9E+09,9E+09,9E+09]];
    !***********************************************************
    !
    ! Module: Module1
    !
    !
    ! Author: SEARHOS
    !
    ! Version: 1.0
    !
    !***********************************************************
    !***********************************************************
    !
    ! Procedure main
    !
    ! This is the entry point of your program
    !
    !***********************************************************
    PROC main()
        MoveJ Target_170,v10,fine,tool0\WObj:=wobj0;
        MoveC Target_180,Target_190,v10,fine,tool0\WObj:=wobj0;
        MoveC Target_200,Target_210,v10,fine,tool0\WObj:=wobj0;
    ENDPROC
    PROC Path_10()
        MoveL Target_50,v50,fine,tool0\WObj:=wobj0;
        MoveC Target_20,Target_60,v50,fine,tool0\WObj:=wobj0;
        MoveC Target_40,Target_50,v50,fine,tool0\WObj:=wobj0;
    ENDPROC
    PROC Path_20()
        MoveL Target_40,v1000,z100,tool0\WObj:=wobj0;
        MoveL Target_50,v1000,z100,tool0\WObj:=wobj0;
        MoveL Target_60,v1000,z100,tool0\WObj:=wobj0;
    ENDPROC
    PROC Path_30()
        MoveJ Target_70,v10,fine,tool0\WObj:=wobj0;
        MoveC Target_80,Target_90,v10,fine,tool0\WObj:=wobj0;
        MoveC Target_100,Target_110,v10,fine,tool0\WObj:=wobj0;
    ENDPROC
    PROC Path_40()
        MoveJ Target_120,v10,fine,tool0\WObj:=wobj0;
        MoveC Target_130,Target_140,v10,fine,tool0\WObj:=wobj0;
        MoveC Target_150,Target_160,v10,fine,tool0\WObj:=wobj0;
    ENDPROC
    PROC Path_50()
        MoveJ Target_170,v10,fine,tool0\WObj:=wobj0;
        MoveC Target_180,Target_190,v10,fine,tool0\WObj:=wobj0;
        MoveC Target_200,Target_210,v10,fine,tool0\WObj:=wobj0;
    ENDPROC
    PROC Path_60()
        MoveL Target_220,v1000,z100,tool0\WObj:=wobj0;
        MoveC\Conc,Target_230,Target_240,v1000,z100,tool0\WObj:=wobj0;
        MoveC\Conc,Target_250,Target_260,v1000,z100,tool0\WObj:=wobj0;
    ENDPROC
ENDMODULE
