# The servo outputs each shipped program is built for: the servos of the
# module type it runs (scenes/modules/<type>.yaml). They decide which analog
# inputs remain for the ADC channels (hal_pic_board.h). Read by both PIC
# builds of the shipped programs: hal-pic/CMakeLists.txt (tools/pic-build.sh)
# and firmware/CMakeLists.txt (the main build with -DCHAINSIM_PIC=ON).
set(PIC_SERVOS_central 0)
set(PIC_SERVOS_rotation 2)
set(PIC_SERVOS_extension 2)
set(PIC_SERVOS_helicoidal 1)
set(PIC_SERVOS_support 1)
set(PIC_SERVOS_touch 0)
set(PIC_SERVOS_traveller 0)
set(PIC_SERVOS_passive 0)
