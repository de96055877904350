# gdb script (tools/lavapipe-profile.sh): logs the name and address of every function
# lavapipe's LLVM JIT compiles, as `NAME 0xADDRESS` lines in $LVP_PROFILE_OUT/jit.txt,
# and copies its code to code_ADDRESS.bin beside it (for `objdump -b binary`).
import os
import gdb

out_dir = os.environ["LVP_PROFILE_OUT"]
log = open(os.path.join(out_dir, "jit.txt"), "w")
for setting in ["breakpoint pending on", "pagination off", "confirm off",
                "print thread-events off"]:
    gdb.execute("set " + setting)
gdb.execute("break LLVMGetPointerToGlobal")
gdb.execute("run")
while True:
    try:
        name = gdb.parse_and_eval("(const char*)LLVMGetValueName($rsi)").string()
        gdb.execute("finish", to_string=True)
        address = int(gdb.parse_and_eval("$rax"))
        log.write("%s 0x%x\n" % (name, address))
        log.flush()
        code = os.path.join(out_dir, "code_%x.bin" % address)
        # The function's code, as much of the next 64 KiB as is mapped.
        for size in [0x10000, 0x8000, 0x4000, 0x1000]:
            try:
                gdb.execute("dump binary memory %s %d %d" % (code, address, address + size))
                break
            except gdb.error:
                pass
        gdb.execute("continue")
    except gdb.error:
        # The program has exited.
        break
gdb.execute("quit")
